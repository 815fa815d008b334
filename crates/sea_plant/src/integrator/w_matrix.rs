//! The implicit step's matrix `W = I - g Jf` and its solve.

use crate::dynamics::{joint_diagonal, PlantData};
use crate::error::{Error, Result};
use crate::plant::{MotorInput, Plant};
use nalgebra::DVector;
use sea_dyn::dense::{cholesky_in_place, cholesky_solve_in_place, copy_contiguous};

/// Prepares the implicit step's matrix `W = I - g Jf` at the last evaluated state, with `g`
/// the step scale (`gamma dt`). `Jf` keeps the stiff linear terms exactly: springs, dampers,
/// the motor velocity loop and the Baumgarte terms, with `M` and `J` frozen (see
/// `integrator.rs`). Elastic motors are eliminated per joint, leaving an nv-size system.
pub(crate) fn prepare_implicit(plant: &Plant, pd: &mut PlantData, g: f64) -> Result<()> {
    let actuation = &plant.actuation;
    pd.w_g = g;
    joint_diagonal(plant, &mut pd.diagonal);
    for (e, p) in actuation.elastic.iter().enumerate() {
        let (torque_driven, gain) = match plant.motor_input {
            MotorInput::VelocityLoop { gain } if !pd.saturated[e] => (false, gain),
            _ => (true, 0.0),
        };
        let coupling = if torque_driven {
            g / p.motor_inertia
        } else {
            0.0
        };
        let eta = p.ratio;
        let den = 1.0 + g * gain + coupling * (g * eta * eta * p.stiffness + eta * eta * p.damping);
        let a1 = coupling * eta * (g * p.stiffness + p.damping) / den;
        let t1 = (g * p.stiffness + p.damping) * (eta * a1 - 1.0);
        pd.w_den[e] = den;
        pd.w_a1[e] = a1;
        pd.w_t1[e] = t1;
        pd.w_torque_driven[e] = torque_driven;
        pd.w_gain[e] = gain;
        let vj = 6 + actuation.elastic_joints[e];
        pd.diagonal[vj] -= g * t1;
    }
    pd.w_factor
        .factor(&pd.data.mass_matrix, &pd.diagonal)
        .map_err(|e| e.during("factorising the implicit step matrix"))?;
    if plant.contacts.is_empty() {
        return Ok(());
    }
    copy_contiguous(&mut pd.w_jacobian, &pd.contact_jacobian);
    pd.w_factor
        .schur_complement(&pd.w_jacobian, &mut pd.w_linv_jt_t, &mut pd.w_schur);
    cholesky_in_place(&mut pd.w_schur).map_err(|i| {
        Error::numerical(
            "implicit step",
            format!("contact constraints are degenerate (pivot {i})"),
        )
    })
}

/// Solves `W k = r` (tangent vectors, size nd) with the matrix of [`prepare_implicit`].
///
/// Per elastic joint the motor unknowns are `k_thetadot = a0 + a1 k_sdot`,
/// `k_theta = r_theta + g k_thetadot`, and the torque perturbation `t0 + t1 k_sdot`; the
/// velocity part solves `[M~ J^T; J 0] [z; -df] = [B (t0 + t1 r_sdot); c]` with
/// `c = -(K_d J r_nu + K_p J (r_q + g r_nu)) / (1 + g K_d + g^2 K_p)`; then `k_nu = r_nu + g z`,
/// `k_q = r_q + g k_nu`.
pub(crate) fn solve_implicit(
    plant: &Plant,
    pd: &mut PlantData,
    r: &DVector<f64>,
    k: &mut DVector<f64>,
) {
    let layout = plant.layout();
    let (nv, ne) = (layout.nv, layout.ne);
    let g = pd.w_g;
    let (o_theta, o_nu, o_thetadot) = (nv, nv + ne, 2 * nv + ne);
    let actuation = &plant.actuation;
    // z <- B (t0 + t1 r_sdot), keeping a0 per joint in k's thetadot slots for later.
    let z = &mut pd.scratch_v;
    z.fill(0.0);
    for (e, p) in actuation.elastic.iter().enumerate() {
        let vj = 6 + actuation.elastic_joints[e];
        let (r_s, r_theta, r_thetadot) = (r[vj], r[o_theta + e], r[o_thetadot + e]);
        let eta = p.ratio;
        let coupling = if pd.w_torque_driven[e] {
            g / p.motor_inertia
        } else {
            0.0
        };
        let a0 = (r_thetadot
            - coupling * (eta * eta * p.stiffness * r_theta - eta * p.stiffness * r_s))
            / pd.w_den[e];
        let t0 = p.stiffness * (eta * r_theta - r_s) + (g * p.stiffness + p.damping) * eta * a0;
        z[vj] = t0 + pd.w_t1[e] * r[o_nu + vj];
        k[o_thetadot + e] = a0;
    }
    pd.w_factor.solve_lt(z.as_mut_slice());
    if !plant.contacts.is_empty() {
        let kp = plant.baumgarte_kp;
        let kd = plant.baumgarte_kd;
        let scale = 1.0 / (1.0 + g * kd + g * g * kp);
        // c = -J (K_d r_nu + K_p (r_q + g r_nu)) / (1 + g K_d + g^2 K_p), the velocity
        // combination formed first so that J is applied once (gemv over its columns).
        let combination = &mut pd.scratch_v2;
        for i in 0..nv {
            let r_nu = r[o_nu + i];
            combination[i] = kd * r_nu + kp * (r[i] + g * r_nu);
        }
        let rhs = &mut pd.constraint_rhs;
        rhs.gemv(-scale, &pd.w_jacobian, combination, 0.0);
        rhs.gemv(-1.0, &pd.w_linv_jt_t, z, 1.0);
        cholesky_solve_in_place(&pd.w_schur, rhs.as_mut_slice());
        z.gemv_tr(1.0, &pd.w_linv_jt_t, rhs, 1.0);
    }
    pd.w_factor.solve_l(z.as_mut_slice());
    for i in 0..nv {
        let k_nu = r[o_nu + i] + g * z[i];
        k[o_nu + i] = k_nu;
        k[i] = r[i] + g * k_nu;
    }
    for e in 0..ne {
        let vj = 6 + actuation.elastic_joints[e];
        let k_thetadot = k[o_thetadot + e] + pd.w_a1[e] * k[o_nu + vj];
        k[o_thetadot + e] = k_thetadot;
        k[o_theta + e] = r[o_theta + e] + g * k_thetadot;
    }
}
