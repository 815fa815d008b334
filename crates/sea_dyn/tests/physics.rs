//! Physics identities of the floating-base dynamics on seeded random URDF trees
//! M from RNEA columns, `nu^T (Mdot - 2C) nu = 0`, power balance,
//! energy and momentum conservation in free flight, momentum = A_G nu = sum over the links,
//! CoM Jacobian, frame Jacobians, `Jdot nu` and `Adot_G nu` against finite differences along
//! `integrate`, and the centroidal split against a dense Schur complement.

use crate::common;

use common::*;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};
use sea_dyn::{
    bias_forces, centroidal_momentum, centroidal_momentum_bias, centroidal_momentum_matrix, com,
    com_jacobian, crba, frame_jacobian, frame_jacobian_dot_v, frame_placement, gravity_forces,
    integrate, rnea, CentroidalSplit, Data, Model,
};

fn dv(v: &[f64]) -> DVector<f64> {
    DVector::from_column_slice(v)
}

fn v6(v: &Vector6<f64>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

fn v3(v: &Vector3<f64>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

fn mass_matrix(model: &Model, data: &mut Data, q: &[f64]) -> DMatrix<f64> {
    crba(model, data, q).clone()
}

fn bias(model: &Model, data: &mut Data, q: &[f64], nu: &[f64]) -> DVector<f64> {
    bias_forces(model, data, q, nu).clone()
}

/// `nudot = M^-1 (tau - h)`.
fn forward_dynamics(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &[f64],
    tau: &DVector<f64>,
) -> DVector<f64> {
    let m = mass_matrix(model, data, q);
    let h = bias(model, data, q, nu);
    m.cholesky().expect("M positive definite").solve(&(tau - h))
}

/// Independent momentum and kinetic energy from the URDF description: for every link with an
/// inertial, `v_c = v_link + omega x (R c)`, world inertia `R R_in I R_in^T R^T`; uses only
/// `frame_placement` and `frame_jacobian` of the links (both checked separately).
struct LinkSums {
    mass: f64,
    com: Vector3<f64>,
    linear: Vector3<f64>,
    angular_com: Vector3<f64>,
    kinetic: f64,
}

fn link_sums(model: &Model, data: &mut Data, desc: &RobotDesc, q: &[f64], nu: &[f64]) -> LinkSums {
    let nu_v = dv(nu);
    let mut parts = Vec::new();
    for link in &desc.links {
        let Some(inertial) = &link.inertial else {
            continue;
        };
        let id = model.frame_id(&link.name).unwrap();
        sea_dyn::forward_kinematics(model, data, q);
        let pose = frame_placement(model, data, id);
        let j = frame_jacobian(model, data, q, id).clone();
        let twist = &j * &nu_v;
        let v_o = Vector3::new(twist[0], twist[1], twist[2]);
        let w = Vector3::new(twist[3], twist[4], twist[5]);
        let r = pose.rotation;
        let c_offset = r * Vector3::from(inertial.xyz);
        let p_c = pose.translation + c_offset;
        let v_c = v_o + w.cross(&c_offset);
        let r_in = r * rpy(inertial.rpy);
        let i_world = r_in * inertial.inertia * r_in.transpose();
        parts.push((inertial.mass, p_c, v_c, i_world, w));
    }
    let mass: f64 = parts.iter().map(|p| p.0).sum();
    let com = parts.iter().map(|p| p.1 * p.0).sum::<Vector3<f64>>() / mass;
    let mut linear = Vector3::zeros();
    let mut angular_com = Vector3::zeros();
    let mut kinetic = 0.0;
    for (m, p_c, v_c, i_world, w) in parts {
        linear += v_c * m;
        angular_com += i_world * w + (p_c - com).cross(&(v_c * m));
        kinetic += 0.5 * (m * v_c.norm_squared() + w.dot(&(i_world * w)));
    }
    LinkSums {
        mass,
        com,
        linear,
        angular_com,
        kinetic,
    }
}

#[test]
fn kinematics_and_com_match_an_independent_evaluation_of_the_urdf() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        assert_eq!(
            model.frames.len(),
            desc.links.len(),
            "seed {seed}: one frame per link"
        );
        assert_eq!(model.n_joints(), desc.moving_joints().len(), "seed {seed}");
        assert!((model.total_mass() - desc.total_mass()).abs() < 1e-12 * desc.total_mass());
        let mut rng = Lcg::new(1000 + seed);
        for _ in 0..3 {
            let q = random_q(&mut rng, model.nq());
            let poses = desc.link_poses(
                Vector3::new(q[0], q[1], q[2]),
                [q[3], q[4], q[5], q[6]],
                |j| joint_value(&model, &desc, &q, j),
            );
            sea_dyn::forward_kinematics(&model, &mut data, &q);
            for (l, link) in desc.links.iter().enumerate() {
                let pose = frame_placement(&model, &data, model.frame_id(&link.name).unwrap());
                let (r, p) = poses[l];
                assert!(
                    (pose.rotation - r).amax() < 1e-12 && (pose.translation - p).amax() < 1e-12,
                    "seed {seed}: pose of link {} differs:\n{:?}\n{:?}",
                    link.name,
                    pose,
                    (r, p)
                );
            }
            // CoM from the URDF inertials.
            let mass = desc.total_mass();
            let mut c = Vector3::zeros();
            for (l, link) in desc.links.iter().enumerate() {
                if let Some(i) = &link.inertial {
                    c += (poses[l].1 + poses[l].0 * Vector3::from(i.xyz)) * i.mass;
                }
            }
            c /= mass;
            let c_lib = com(&model, &mut data, &q);
            assert!(
                (c - c_lib).amax() < 1e-12,
                "seed {seed}: com {c_lib} vs {c}"
            );
        }
    }
}

#[test]
fn mass_matrix_equals_rnea_columns_and_is_symmetric_positive_definite() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(2000 + seed);
        let nv = model.nv();
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, nv, 1.0);
        let nudot = random_v(&mut rng, nv, 1.0);
        let zero = vec![0.0; nv];

        let m = mass_matrix(&model, &mut data, &q);
        let scale = m.amax();
        let g0 = rnea(&model, &mut data, &q, &zero, &zero).clone();
        let mut from_rnea = DMatrix::zeros(nv, nv);
        for k in 0..nv {
            let mut e = vec![0.0; nv];
            e[k] = 1.0;
            let column = rnea(&model, &mut data, &q, &zero, &e).clone() - &g0;
            from_rnea.set_column(k, &column);
        }
        assert_close_mat(
            &format!("seed {seed}: M vs RNEA columns"),
            &m,
            &from_rnea,
            1e-12,
            scale,
        );
        assert_close_mat(
            &format!("seed {seed}: M symmetric"),
            &m,
            &m.transpose(),
            1e-14,
            scale,
        );
        // The CRBA that reuses RNEA's body inertias gives the same matrix at the same q.
        let _ = sea_dyn::bias_forces(&model, &mut data, &q, &nu);
        let after_rnea = sea_dyn::crba_after_rnea(&model, &mut data).clone();
        assert_close_mat(
            &format!("seed {seed}: crba_after_rnea vs crba"),
            &after_rnea,
            &m,
            1e-15,
            scale,
        );
        let eig = m.clone().symmetric_eigen().eigenvalues;
        assert!(
            eig.min() > 1e-9 * scale,
            "seed {seed}: M not positive definite: {eig}"
        );

        // G, h and the full inverse dynamics.
        let g = gravity_forces(&model, &mut data, &q).clone();
        assert_close_vec(
            &format!("seed {seed}: G = rnea(q, 0, 0)"),
            &g,
            &g0,
            1e-13,
            g0.amax(),
        );
        let h = bias(&model, &mut data, &q, &nu);
        let h_rnea = rnea(&model, &mut data, &q, &nu, &zero).clone();
        assert_close_vec(
            &format!("seed {seed}: h = rnea(q, nu, 0)"),
            &h,
            &h_rnea,
            1e-13,
            h.amax(),
        );
        let tau = rnea(&model, &mut data, &q, &nu, &nudot).clone();
        let expected = &m * dv(&nudot) + &h;
        assert_close_vec(
            &format!("seed {seed}: rnea = M nudot + h"),
            &tau,
            &expected,
            1e-12,
            tau.amax(),
        );
        // Gravity: the base force is m g, and G is linear in g.
        let total = model.total_mass();
        let gvec = model.gravity;
        for k in 0..3 {
            assert!(
                (g[k] + total * gvec[k]).abs() < 1e-12 * total * 10.0,
                "seed {seed}: G base force {g}"
            );
        }

        // Kinetic energy 0.5 nu^T M nu equals the sum over the URDF links.
        let sums = link_sums(&model, &mut data, &desc, &q, &nu);
        let t = 0.5 * dv(&nu).dot(&(&m * dv(&nu)));
        assert!(
            (t - sums.kinetic).abs() < 1e-12 * sums.kinetic.max(1.0),
            "seed {seed}: kinetic energy {t} vs links {}",
            sums.kinetic
        );
    }
}

#[test]
fn mdot_minus_two_c_is_skew_along_the_motion_and_power_balance_holds() {
    let h = 1e-3;
    for seed in seeds() {
        let desc = random_robot(seed);
        let mut model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(3000 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        let nu_v = dv(&nu);

        let mdot = central_diff_mat(h, |t| {
            mass_matrix(&model, &mut data, &flow(&model, &q, &nu, t))
        });
        let c_nu = bias(&model, &mut data, &q, &nu) - gravity_forces(&model, &mut data, &q).clone();
        let quad_mdot = nu_v.dot(&(&mdot * &nu_v));
        let quad_c = nu_v.dot(&c_nu);
        let scale = mdot.norm() * nu_v.norm_squared();
        assert!(
            (quad_mdot - 2.0 * quad_c).abs() < 1e-6 * scale,
            "seed {seed}: nu^T Mdot nu = {quad_mdot}, 2 nu^T C nu = {}, scale {scale}",
            2.0 * quad_c
        );

        // Power balance without gravity: dT/dt = nu^T M nudot + 0.5 nu^T Mdot nu = nu^T tau
        // with nudot = M^-1 (tau - h).
        model.gravity = Vector3::zeros();
        let tau = dv(&random_v(&mut rng, model.nv(), 2.0));
        let nudot = forward_dynamics(&model, &mut data, &q, &nu, &tau);
        let m = mass_matrix(&model, &mut data, &q);
        let t_dot = nu_v.dot(&(&m * &nudot)) + 0.5 * quad_mdot;
        let power = nu_v.dot(&tau);
        let scale = power.abs() + nu_v.norm() * (tau.norm() + m.norm() * nudot.norm());
        assert!(
            (t_dot - power).abs() < 1e-6 * scale,
            "seed {seed}: dT/dt = {t_dot} but nu^T tau = {power}"
        );
    }
}

/// `Theta' = dexp^-1_Theta(omega)` for `R = exp(Theta) R0`, `Rdot = [omega]x R`, up to the
/// terms RK4 needs.
fn dexp_inv(theta: &Vector3<f64>, omega: &Vector3<f64>) -> Vector3<f64> {
    omega - theta.cross(omega) * 0.5 + theta.cross(&theta.cross(omega)) / 12.0
}

/// One RKMK4 step of `qdot = nu` (through `integrate`), `nudot = M^-1 (tau - h)`, `tau = 0`.
fn rk4_step(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &DVector<f64>,
    dt: f64,
) -> (Vec<f64>, DVector<f64>) {
    let nv = model.nv();
    let zero = DVector::zeros(nv);
    let stages: [(f64, usize); 4] = [(0.0, 0), (0.5, 0), (0.5, 1), (1.0, 2)];
    let mut ks: Vec<DVector<f64>> = Vec::new(); // corrected configuration velocities
    let mut accs: Vec<DVector<f64>> = Vec::new();
    let mut q_stage = vec![0.0; q.len()];
    for (i, &(a, from)) in stages.iter().enumerate() {
        let (increment, nu_stage) = if i == 0 {
            (DVector::zeros(nv), nu.clone())
        } else {
            (&ks[from] * (a * dt), nu + &accs[from] * (a * dt))
        };
        integrate(model, q, increment.as_slice(), 1.0, &mut q_stage);
        let acc = forward_dynamics(model, data, &q_stage, nu_stage.as_slice(), &zero);
        let theta = Vector3::new(increment[3], increment[4], increment[5]);
        let omega = Vector3::new(nu_stage[3], nu_stage[4], nu_stage[5]);
        let mut k = nu_stage.clone();
        k.fixed_rows_mut::<3>(3)
            .copy_from(&dexp_inv(&theta, &omega));
        ks.push(k);
        accs.push(acc);
    }
    let increment = (&ks[0] + &ks[1] * 2.0 + &ks[2] * 2.0 + &ks[3]) * (dt / 6.0);
    let mut q_next = vec![0.0; q.len()];
    integrate(model, q, increment.as_slice(), 1.0, &mut q_next);
    let nu_next = nu + (&accs[0] + &accs[1] * 2.0 + &accs[2] * 2.0 + &accs[3]) * (dt / 6.0);
    (q_next, nu_next)
}

#[test]
fn free_flight_without_gravity_conserves_energy_and_centroidal_momentum() {
    let (dt, steps) = (1e-4, 1000);
    for seed in seeds() {
        let desc = random_robot(seed);
        let mut model = load(&desc);
        model.gravity = Vector3::zeros();
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(4000 + seed);
        let mut q = random_q(&mut rng, model.nq());
        let mut nu = dv(&random_v(&mut rng, model.nv(), 1.0));
        let energy = |model: &Model, data: &mut Data, q: &[f64], nu: &DVector<f64>| {
            0.5 * nu.dot(&(mass_matrix(model, data, q) * nu))
        };
        let t0 = energy(&model, &mut data, &q, &nu);
        let h0 = centroidal_momentum(&model, &mut data, &q, nu.as_slice());
        let mut max_energy_drift: f64 = 0.0;
        let mut max_momentum_drift: f64 = 0.0;
        for step in 0..steps {
            let (qn, nun) = rk4_step(&model, &mut data, &q, &nu, dt);
            q = qn;
            nu = nun;
            if step % 50 == 49 {
                let t = energy(&model, &mut data, &q, &nu);
                max_energy_drift = max_energy_drift.max((t - t0).abs() / t0);
                let h = centroidal_momentum(&model, &mut data, &q, nu.as_slice());
                max_momentum_drift = max_momentum_drift.max((h - h0).amax() / (h0.amax() + 1e-3));
            }
        }
        let moved = (dv(&q) - dv(&random_q(&mut Lcg::new(4000 + seed), model.nq()))).amax();
        assert!(moved > 1e-3, "seed {seed}: the robot did not move");
        assert!(
            max_energy_drift < 1e-6,
            "seed {seed}: relative energy drift {max_energy_drift:e}"
        );
        assert!(
            max_momentum_drift < 1e-6,
            "seed {seed}: relative momentum drift {max_momentum_drift:e}"
        );
    }
}

#[test]
fn free_fall_with_gravity_conserves_total_energy_and_angular_momentum() {
    let (dt, steps) = (1e-4, 1000);
    for seed in seeds().step_by(2) {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(5000 + seed);
        let mut q = random_q(&mut rng, model.nq());
        let mut nu = dv(&random_v(&mut rng, model.nv(), 1.0));
        let mass = model.total_mass();
        let g = model.gravity;
        let energy = |data: &mut Data, q: &[f64], nu: &DVector<f64>| {
            0.5 * nu.dot(&(mass_matrix(&model, data, q) * nu)) - mass * g.dot(&com(&model, data, q))
        };
        let e0 = energy(&mut data, &q, &nu);
        let t0 = 0.5 * nu.dot(&(mass_matrix(&model, &mut data, &q) * &nu));
        let h0 = centroidal_momentum(&model, &mut data, &q, nu.as_slice());
        for step in 0..steps {
            let (qn, nun) = rk4_step(&model, &mut data, &q, &nu, dt);
            q = qn;
            nu = nun;
            if step % 100 == 99 {
                let time = (step + 1) as f64 * dt;
                let e = energy(&mut data, &q, &nu);
                assert!(
                    (e - e0).abs() < 1e-6 * (t0 + mass * 9.81 * 1.0),
                    "seed {seed}: energy {e} vs {e0}"
                );
                let h = centroidal_momentum(&model, &mut data, &q, nu.as_slice());
                let mut expected = h0;
                for k in 0..3 {
                    expected[k] += mass * g[k] * time;
                }
                let err = (h - expected).amax();
                assert!(
                    err < 1e-6 * (h0.amax() + mass),
                    "seed {seed}: momentum {h} expected {expected}"
                );
            }
        }
    }
}

#[test]
fn centroidal_momentum_equals_a_g_nu_and_the_sum_over_links() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(6000 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        let a_g = centroidal_momentum_matrix(&model, &mut data, &q).clone();
        let h_matrix = &a_g * dv(&nu);
        let h = v6(&centroidal_momentum(&model, &mut data, &q, &nu));
        let scale = h.amax() + 1.0;
        assert_close_vec(
            &format!("seed {seed}: H vs A_G nu"),
            &h,
            &h_matrix,
            1e-12,
            scale,
        );

        let sums = link_sums(&model, &mut data, &desc, &q, &nu);
        let independent = DVector::from_iterator(
            6,
            sums.linear.iter().chain(sums.angular_com.iter()).copied(),
        );
        assert_close_vec(
            &format!("seed {seed}: H vs links"),
            &h,
            &independent,
            1e-12,
            scale,
        );
        assert!((sums.com - com(&model, &mut data, &q)).amax() < 1e-12);
        assert!((sums.mass - model.total_mass()).abs() < 1e-12);

        // CoM Jacobian: m J_com nu = P and J_com nu = d/dt com.
        let j_com = com_jacobian(&model, &mut data, &q).clone();
        let v_com = &j_com * dv(&nu);
        assert_close_vec(
            &format!("seed {seed}: m J_com nu vs P"),
            &(&v_com * model.total_mass()),
            &h.rows(0, 3).into_owned(),
            1e-12,
            scale,
        );
        let fd = central_diff(1e-3, |t| {
            v3(&com(&model, &mut data, &flow(&model, &q, &nu, t)))
        });
        assert_close_vec(
            &format!("seed {seed}: J_com nu vs d/dt com"),
            &v_com,
            &fd,
            1e-7,
            v_com.amax() + 1.0,
        );
    }
}

/// Placement of frame `id` at `integrate(q, nu, t)`.
fn placement_along(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &[f64],
    t: f64,
    id: usize,
) -> sea_dyn::spatial::Pose {
    sea_dyn::forward_kinematics(model, data, &flow(model, q, nu, t));
    frame_placement(model, data, id)
}

/// `[d/dt p; omega]` of frame `id` along `integrate(q, nu, t)` by finite differences.
fn twist_by_differences(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &[f64],
    id: usize,
) -> DVector<f64> {
    let v = central_diff(1e-3, |t| {
        v3(&placement_along(model, data, q, nu, t, id).translation)
    });
    let w = angular_velocity(1e-3, |t| {
        placement_along(model, data, q, nu, t, id).rotation
    });
    DVector::from_iterator(6, v.iter().chain(w.iter()).copied())
}

#[test]
fn frame_jacobians_match_finite_differences_of_the_placements() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(7000 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        for id in 0..model.frames.len() {
            let j = frame_jacobian(&model, &mut data, &q, id).clone();
            let twist = &j * dv(&nu);
            let fd = twist_by_differences(&model, &mut data, &q, &nu, id);
            assert_close_vec(
                &format!("seed {seed}: J nu of frame {}", model.frames[id].name),
                &twist,
                &fd,
                1e-7,
                twist.amax() + 1.0,
            );
            // Pure base motions: the base columns.
            for k in 0..6 {
                let mut e = vec![0.0; model.nv()];
                e[k] = 1.0;
                let col = j.column(k).into_owned();
                let fd = twist_by_differences(&model, &mut data, &q, &e, id);
                assert_close_vec(
                    &format!("seed {seed}: base column {k}"),
                    &col,
                    &fd,
                    1e-7,
                    5.0,
                );
            }
        }
    }
}

/// `Jdot nu` read off RNEA's body accelerations (gravity removed) right after `bias_forces`
/// equals the pass over the frame's support, for every frame of the random trees; a wrong sign
/// of the gravity correction would be off by 9.81 m/s^2.
#[test]
fn jdot_nu_after_bias_forces_matches_the_support_pass() {
    for seed in seeds() {
        let model = load(&random_robot(seed));
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(8100 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        sea_dyn::bias_forces(&model, &mut data, &q, &nu);
        for id in 0..model.frames.len() {
            let shortcut = v6(
                &sea_dyn::jacobian::frame_bias_acceleration_after_bias_forces(&model, &data, id),
            );
            let pass = v6(&sea_dyn::jacobian::frame_bias_acceleration(
                &model, &mut data, id,
            ));
            assert_close_vec(
                &format!("seed {seed}: Jdot nu of frame {}", model.frames[id].name),
                &shortcut,
                &pass,
                1e-12,
                pass.amax() + 1.0,
            );
        }
    }
}

/// The frame velocity read off the body velocities equals `J nu`, and a Jacobian written into
/// rows of a stacked matrix equals the frame Jacobian there and leaves the other rows alone,
/// for every frame of the random trees.
#[test]
fn frame_velocity_and_stacked_rows_match_the_frame_jacobian() {
    for seed in seeds() {
        let model = load(&random_robot(seed));
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(8200 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        sea_dyn::bias_forces(&model, &mut data, &q, &nu);
        for id in 0..model.frames.len() {
            let name = &model.frames[id].name;
            let velocity = v6(&sea_dyn::jacobian::frame_velocity_from_kinematics(
                &model, &data, id,
            ));
            sea_dyn::jacobian::frame_jacobian_from_kinematics(&model, &mut data, id);
            let jacobian = data.frame_jacobian.clone();
            let j_nu = &jacobian * DVector::from_column_slice(&nu);
            assert_close_vec(
                &format!("seed {seed}: J nu of frame {name}"),
                &velocity,
                &j_nu,
                1e-12,
                j_nu.amax() + 1.0,
            );
            let mut stacked = DMatrix::from_element(13, model.nv(), 7.0);
            sea_dyn::jacobian::frame_jacobian_into_rows(&model, &data, id, &mut stacked, 6);
            assert_eq!(
                stacked.rows(6, 6),
                jacobian,
                "seed {seed}: rows of frame {name}"
            );
            for r in (0..6).chain(12..13) {
                assert!(
                    stacked.row(r).iter().all(|&v| v == 7.0),
                    "seed {seed}: row {r} changed by frame {name}"
                );
            }
        }
    }
}

#[test]
fn jdot_nu_matches_the_derivative_of_j_nu_at_constant_nu() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(8000 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        for id in 0..model.frames.len() {
            let jdot_nu = v6(&frame_jacobian_dot_v(&model, &mut data, &q, &nu, id));
            let fd = central_diff(1e-3, |t| {
                frame_jacobian(&model, &mut data, &flow(&model, &q, &nu, t), id).clone() * dv(&nu)
            });
            assert_close_vec(
                &format!("seed {seed}: Jdot nu of frame {}", model.frames[id].name),
                &jdot_nu,
                &fd,
                1e-7,
                jdot_nu.amax() + 1.0,
            );
            // It is also the frame origin's classical acceleration (second derivative).
            let h = 1e-3;
            let mut p = |t: f64| placement_along(&model, &mut data, &q, &nu, t, id).translation;
            let (p0, p1, m1, p2, m2) = (p(0.0), p(h), p(-h), p(2.0 * h), p(-2.0 * h));
            let acc = ((p1 + m1) * 16.0 - (p2 + m2) - p0 * 30.0) / (12.0 * h * h);
            let err = (acc - Vector3::new(jdot_nu[0], jdot_nu[1], jdot_nu[2])).amax();
            assert!(
                err < 1e-5 * (jdot_nu.amax() + 1.0),
                "seed {seed}: pddot {acc} vs Jdot nu {jdot_nu}"
            );
        }
    }
}

#[test]
fn centroidal_momentum_bias_matches_the_derivative_of_a_g_nu() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let mut model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(9000 + seed);
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, model.nv(), 1.0);
        let bias = v6(&centroidal_momentum_bias(&model, &mut data, &q, &nu));
        let fd = central_diff(1e-3, |t| {
            centroidal_momentum_matrix(&model, &mut data, &flow(&model, &q, &nu, t)).clone()
                * dv(&nu)
        });
        assert_close_vec(
            &format!("seed {seed}: Adot_G nu"),
            &bias,
            &fd,
            1e-7,
            bias.amax() + 1.0,
        );

        // Without gravity the base rows of RNEA are the rate of the total momentum (force, and
        // moment about the base origin): Hdot = A_G nudot + Adot_G nu.
        model.gravity = Vector3::zeros();
        let nudot = random_v(&mut rng, model.nv(), 1.0);
        let tau = rnea(&model, &mut data, &q, &nu, &nudot).clone();
        let a_g = centroidal_momentum_matrix(&model, &mut data, &q).clone();
        let hdot = &a_g * dv(&nudot) + &bias;
        let c_rel = com(&model, &mut data, &q) - Vector3::new(q[0], q[1], q[2]);
        let force = Vector3::new(hdot[0], hdot[1], hdot[2]);
        let moment = Vector3::new(hdot[3], hdot[4], hdot[5]) + c_rel.cross(&force);
        let expected = DVector::from_iterator(6, force.iter().chain(moment.iter()).copied());
        assert_close_vec(
            &format!("seed {seed}: base wrench vs Hdot"),
            &tau.rows(0, 6).into_owned(),
            &expected,
            1e-12,
            tau.amax() + 1.0,
        );
    }
}

#[test]
fn centroidal_split_matches_the_dense_schur_complement() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        let mut data = Data::new(&model);
        let mut rng = Lcg::new(10_000 + seed);
        let (n, nv) = (model.n_joints(), model.nv());
        let q = random_q(&mut rng, model.nq());
        let nu = random_v(&mut rng, nv, 1.0);
        let m = mass_matrix(&model, &mut data, &q);
        let h = bias(&model, &mut data, &q, &nu);
        // Two frames, preferably distinct, stacked (k = 12).
        let f1 = rng.below(model.frames.len());
        let f2 = (f1 + 1 + rng.below(model.frames.len() - 1)) % model.frames.len();
        let mut j = DMatrix::zeros(12, nv);
        j.rows_mut(0, 6)
            .copy_from(frame_jacobian(&model, &mut data, &q, f1));
        j.rows_mut(6, 6)
            .copy_from(frame_jacobian(&model, &mut data, &q, f2));

        let mut split = CentroidalSplit::new(n, 12);
        split.compute(&m, &h, &j).unwrap();

        let m_b_inv = m.view((0, 0), (6, 6)).into_owned().try_inverse().unwrap();
        let m_jb = m.view((6, 0), (n, 6)).into_owned();
        let m_bj = m.view((0, 6), (6, n)).into_owned();
        let mbar = m.view((6, 6), (n, n)) - &m_jb * &m_b_inv * &m_bj;
        let jbar_t = j.view((0, 6), (12, n)).transpose()
            - &m_jb * &m_b_inv * j.view((0, 0), (12, 6)).transpose();
        let hbar = h.rows(6, n) - &m_jb * &m_b_inv * h.rows(0, 6);
        let scale = m.amax();
        assert_close_mat(
            &format!("seed {seed}: Mbar"),
            &split.mbar,
            &mbar,
            1e-10,
            scale,
        );
        assert_close_mat(
            &format!("seed {seed}: Jbar^T"),
            &split.jbar_t,
            &jbar_t,
            1e-10,
            j.amax() + 1.0,
        );
        assert_close_vec(
            &format!("seed {seed}: hbar"),
            &split.h_j_centroidal,
            &hbar,
            1e-10,
            h.amax() + 1.0,
        );
        assert_close_mat(
            &format!("seed {seed}: Mbar symmetric"),
            &split.mbar,
            &split.mbar.transpose(),
            1e-12,
            scale,
        );
        assert!(
            split.mbar.clone().cholesky().is_some(),
            "seed {seed}: Mbar not positive definite"
        );
        // Mbar x without forming Mbar.
        let x = dv(&random_v(&mut rng, n, 1.0));
        let mut mbar_x = DVector::zeros(n);
        split.mbar_times(&m, x.as_slice(), mbar_x.as_mut_slice());
        let expected = &mbar * &x;
        assert_close_vec(
            &format!("seed {seed}: Mbar x"),
            &mbar_x,
            &expected,
            1e-10,
            expected.amax() + 1.0,
        );

        // Joint dynamics after eliminating the base: Mbar sddot = Jbar^T f - hbar + tau.
        for _ in 0..3 {
            let f = dv(&random_v(&mut rng, 12, 5.0));
            let tau = dv(&random_v(&mut rng, n, 5.0));
            let mut rhs = j.transpose() * &f - &h;
            for k in 0..n {
                rhs[6 + k] += tau[k];
            }
            let nudot = m.clone().cholesky().unwrap().solve(&rhs);
            let sddot = nudot.rows(6, n).into_owned();
            let lhs = &split.mbar * &sddot;
            let expected = &split.jbar_t * &f - &split.h_j_centroidal + &tau;
            assert_close_vec(
                &format!("seed {seed}: reduced joint dynamics"),
                &lhs,
                &expected,
                1e-9,
                expected.amax() + 1.0,
            );
        }
    }
}

#[test]
fn random_trees_cover_every_joint_type_and_massless_leaves() {
    let mut seen = [false; 4];
    let mut massless = 0;
    let mut sizes = Vec::new();
    for seed in seeds() {
        let desc = random_robot(seed);
        sizes.push(desc.links.len());
        for j in &desc.joints {
            seen[j.kind as usize] = true;
            let norm = Vector3::from(j.axis).norm();
            assert!(norm > 0.05, "axis too small");
        }
        massless += desc.links.iter().filter(|l| l.inertial.is_none()).count();
        // Principal moments satisfy the triangle inequality and are positive.
        for l in desc.links.iter().filter_map(|l| l.inertial.as_ref()) {
            let e = l.inertia.symmetric_eigen().eigenvalues;
            assert!(e.min() > 0.0);
            assert!(e.sum() - 2.0 * e.max() > 0.0);
            assert!((0.2..3.0).contains(&l.mass));
        }
    }
    assert!(seen.iter().all(|s| *s), "joint types seen: {seen:?}");
    assert!(massless >= 20);
    assert!(
        sizes.iter().all(|n| (6..=15).contains(n)),
        "sizes {sizes:?}"
    );
    assert!(
        sizes.iter().any(|n| *n >= 12) && sizes.iter().any(|n| *n <= 9),
        "sizes {sizes:?}"
    );
}
