//! The implicit step's matrix `W = I - g Jf` and its solve.

use crate::dynamics::{joint_diagonal, PlantData};
use crate::error::{Error, Result};
use crate::plant::{MotorInput, Plant};
use nalgebra::DVector;
use sea_dyn::dense::{cholesky_in_place, cholesky_solve_in_place, gemv_few_rows, gemv_tr_few_rows};

/// One elastic joint's motor unknowns eliminated from `W k = r`, for the step scale `g`: with
/// `r_s`, `r_nu`, `r_theta`, `r_thetadot` the joint's entries of `r`,
/// `k_thetadot = a0 + a1 k_sdot`, `a0 = inv_den r_thetadot - a0_theta r_theta + a0_s r_s`, and
/// the joint torque's perturbation `t0 + t1 k_sdot`,
/// `t0 = K (eta r_theta - r_s) + t0_a0 a0`. The coefficients (divisions included) are
/// computed once per step in [`prepare_implicit`]; the two stage solves only multiply.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MotorElimination {
    inv_den: f64,
    a0_theta: f64,
    a0_s: f64,
    a1: f64,
    t0_a0: f64,
    t1: f64,
}

/// Prepares the implicit step's matrix `W = I - g Jf` at the last evaluated state, with `g`
/// the step scale (`gamma dt`). `Jf` keeps the stiff linear terms exactly: springs, dampers,
/// the motor velocity loop and the Baumgarte terms, with `M` and `J` frozen (see
/// `integrator.rs`). Elastic motors are eliminated per joint, leaving an nv-size system.
pub(crate) fn prepare_implicit(plant: &Plant, pd: &mut PlantData, g: f64) -> Result<()> {
    let actuation = &plant.actuation;
    pd.w_g = g;
    joint_diagonal(plant, &mut pd.diagonal);
    for (e, p) in actuation.elastic.iter().enumerate() {
        // A torque-driven (or saturated) motor's acceleration follows the torques through its
        // inertia; a velocity-looped one is held by the loop.
        let (torque_driven, gain) = match plant.motor_input {
            MotorInput::VelocityLoop { gain } if !pd.saturated[e] => (false, gain),
            _ => (true, 0.0),
        };
        let coupling = if torque_driven {
            g / p.motor_inertia
        } else {
            0.0
        };
        let (eta, stiffness) = (p.ratio, p.stiffness);
        let spring_damper = g * stiffness + p.damping;
        let den = 1.0 + g * gain + coupling * (g * eta * eta * stiffness + eta * eta * p.damping);
        let a1 = coupling * eta * spring_damper / den;
        let t1 = spring_damper * (eta * a1 - 1.0);
        pd.w_motor[e] = MotorElimination {
            inv_den: 1.0 / den,
            a0_theta: coupling * eta * eta * stiffness / den,
            a0_s: coupling * eta * stiffness / den,
            a1,
            t0_a0: spring_damper * eta,
            t1,
        };
        let vj = 6 + actuation.elastic_joints[e];
        pd.diagonal[vj] -= g * t1;
    }
    pd.w_factor
        .factor(&pd.data.mass_matrix, &pd.diagonal)
        .map_err(|e| e.during("factorising the implicit step matrix"))?;
    if plant.contacts.is_empty() {
        return Ok(());
    }
    // J at the step start moves to the step's buffer; the next evaluation overwrites every
    // entry of `contact_jacobian` (or adopts one), so a swap does instead of a copy.
    std::mem::swap(&mut pd.w_jacobian, &mut pd.contact_jacobian);
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
    z.as_mut_slice().fill(0.0);
    for (e, (p, m)) in actuation.elastic.iter().zip(&pd.w_motor).enumerate() {
        let vj = 6 + actuation.elastic_joints[e];
        let (r_s, r_theta, r_thetadot) = (r[vj], r[o_theta + e], r[o_thetadot + e]);
        let a0 = m.inv_den * r_thetadot - m.a0_theta * r_theta + m.a0_s * r_s;
        let t0 = p.stiffness * (p.ratio * r_theta - r_s) + m.t0_a0 * a0;
        z[vj] = t0 + m.t1 * r[o_nu + vj];
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
        gemv_few_rows(
            rhs.as_mut_slice(),
            -scale,
            &pd.w_jacobian,
            combination.as_slice(),
            0.0,
        );
        gemv_few_rows(rhs.as_mut_slice(), -1.0, &pd.w_linv_jt_t, z.as_slice(), 1.0);
        cholesky_solve_in_place(&pd.w_schur, rhs.as_mut_slice());
        gemv_tr_few_rows(z.as_mut_slice(), 1.0, &pd.w_linv_jt_t, rhs.as_slice(), 1.0);
    }
    pd.w_factor.solve_l(z.as_mut_slice());
    for i in 0..nv {
        let k_nu = r[o_nu + i] + g * z[i];
        k[o_nu + i] = k_nu;
        k[i] = r[i] + g * k_nu;
    }
    for e in 0..ne {
        let vj = 6 + actuation.elastic_joints[e];
        let k_thetadot = k[o_thetadot + e] + pd.w_motor[e].a1 * k[o_nu + vj];
        k[o_thetadot + e] = k_thetadot;
        k[o_theta + e] = r[o_theta + e] + g * k_thetadot;
    }
}
