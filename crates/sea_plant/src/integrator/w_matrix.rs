//! The implicit step's matrix `W = I - g Jf`, its factor and its solve, with the buffers they
//! own.

use crate::compliant_forces::{add_foot_to_matrix, foot_matrices};
use crate::error::{Error, Result};
use crate::plant::{MotorInput, Plant};
use crate::workspace::Workspace;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};
use sea_dyn::dense::{
    cholesky_in_place, cholesky_solve_in_place, copy_contiguous, gemv_few_rows, gemv_tr_few_rows,
};
use sea_dyn::linalg::mul_add;
use sea_dyn::tree_factor::TreeFactor;

/// One elastic joint's motor unknowns eliminated from `W k = r`, for the step scale `g`: with
/// `r_s`, `r_nu`, `r_theta`, `r_thetadot` the joint's entries of `r`,
/// `k_thetadot = a0 + a1 k_sdot`, `a0 = inv_den r_thetadot - a0_theta r_theta + a0_s r_s`, and
/// the joint torque's perturbation `t0 + t1 k_sdot`,
/// `t0 = K (Gamma r_theta - r_s) + t0_a0 a0`. The coefficients (divisions included) are
/// computed once per step in [`WMatrix::prepare`]; the two stage solves only multiply.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MotorElimination {
    inv_den: f64,
    a0_theta: f64,
    a0_s: f64,
    a1: f64,
    t0_a0: f64,
    t1: f64,
}

/// `W` (`k = 6 n_contacts`): prepared at a step start, solved once per stage of that step and
/// of the steps that reuse it (`IntegratorCache::set_w_refresh_steps`).
#[derive(Clone, Debug)]
pub(crate) struct WMatrix {
    /// Step scale `g` (`gamma dt`).
    g: f64,
    /// Per elastic joint, the coefficients of the motor elimination (n_e).
    motor: Vec<MotorElimination>,
    /// Diagonal of `M~ = M + diag` (nv): the joint regularisation and the eliminated motors.
    diagonal: Vec<f64>,
    /// `M~ = L~^T L~` (nv x nv, the tree's sparsity).
    factor: TreeFactor,
    /// `J` at the step start (k x nv).
    jacobian: DMatrix<f64>,
    /// `(L~^-T J^T)^T` (k x nv).
    linv_jt_t: DMatrix<f64>,
    /// `J M~^-1 J^T`, then its Cholesky factor (k x k).
    schur: DMatrix<f64>,
    /// The velocity unknowns `z` of a solve (nv).
    z: DVector<f64>,
    /// The velocity combination `K_d r_nu + K_p (r_q + g r_nu)` of a solve (nv).
    combination: DVector<f64>,
    /// The constraint target, then the multipliers' perturbation, of a solve (k).
    constraint: DVector<f64>,
    /// Unilateral contacts: `M + sum g J_c^T (g K_c + D_c) J_c` (nv x nv), factored with the
    /// diagonal.
    augmented: DMatrix<f64>,
    /// Unilateral contacts: `(g K_c + D_c) J_c` of one foot (6 x nv).
    scratch: DMatrix<f64>,
    /// Unilateral contacts: each foot's stiffness and damping at the step start (6 x 6 each).
    foot_stiffness: Vec<Matrix6<f64>>,
    /// See `foot_stiffness`.
    foot_damping: Vec<Matrix6<f64>>,
    /// Joint stops: stiffness and damping per joint at the step start (n each).
    stop_stiffness: Vec<f64>,
    /// See `stop_stiffness`.
    stop_damping: Vec<f64>,
}

impl WMatrix {
    /// Buffers for `plant`.
    pub(crate) fn new(plant: &Plant) -> Self {
        let layout = plant.layout();
        let (nv, ne) = (layout.nv, layout.ne);
        let k = 6 * plant.contacts.len();
        Self {
            g: 0.0,
            motor: vec![MotorElimination::default(); ne],
            diagonal: vec![0.0; nv],
            factor: TreeFactor::new(&plant.model),
            jacobian: DMatrix::zeros(k, nv),
            linv_jt_t: DMatrix::zeros(k, nv),
            schur: DMatrix::zeros(k, k),
            z: DVector::zeros(nv),
            combination: DVector::zeros(nv),
            constraint: DVector::zeros(k),
            augmented: DMatrix::zeros(nv, nv),
            scratch: DMatrix::zeros(6, nv),
            foot_stiffness: vec![Matrix6::zeros(); plant.contacts.len()],
            foot_damping: vec![Matrix6::zeros(); plant.contacts.len()],
            stop_stiffness: vec![0.0; plant.model.n_joints()],
            stop_damping: vec![0.0; plant.model.n_joints()],
        }
    }

    /// Prepares `W = I - g Jf` at the state last evaluated into `ws` (its `M` and `J`), whose
    /// motors saturated as `saturated` says, with `g` the step scale (`gamma dt`). `Jf` keeps
    /// the stiff linear terms exactly: springs, dampers, the motor velocity loop and the
    /// Baumgarte terms, with `M` and `J` frozen (see `integrator/mod.rs`). Elastic motors are
    /// eliminated per joint, leaving an nv-size system.
    pub(crate) fn prepare(
        &mut self,
        plant: &Plant,
        ws: &Workspace,
        saturated: &[bool],
        g: f64,
    ) -> Result<()> {
        let actuation = &plant.actuation;
        self.g = g;
        plant.joint_diagonal(&mut self.diagonal);
        for (e, p) in actuation.elastic.iter().enumerate() {
            // A torque-driven (or saturated) motor's acceleration follows the torques through
            // its inertia; a velocity-looped one is held by the loop.
            let (torque_driven, gain) = match plant.motor_input {
                MotorInput::VelocityLoop { gain } if !saturated[e] => (false, gain),
                _ => (true, 0.0),
            };
            let coupling = if torque_driven {
                g / p.motor_inertia
            } else {
                0.0
            };
            let (ratio, stiffness) = (p.ratio, p.stiffness);
            let spring_damper = g * stiffness + p.damping;
            let den = 1.0
                + g * gain
                + coupling * (g * ratio * ratio * stiffness + ratio * ratio * p.damping);
            let a1 = coupling * ratio * spring_damper / den;
            let t1 = spring_damper * (ratio * a1 - 1.0);
            self.motor[e] = MotorElimination {
                inv_den: 1.0 / den,
                a0_theta: coupling * ratio * ratio * stiffness / den,
                a0_s: coupling * ratio * stiffness / den,
                a1,
                t0_a0: spring_damper * ratio,
                t1,
            };
            let vj = 6 + actuation.elastic_joints[e];
            self.diagonal[vj] -= g * t1;
        }
        if plant.joint_stops.is_some() {
            self.add_stops(ws);
        }
        let factored = if plant.unilateral().is_some() {
            self.augment_with_contacts(plant, ws);
            self.factor.factor(&self.augmented, &self.diagonal)
        } else {
            self.factor.factor(&ws.data.mass_matrix, &self.diagonal)
        };
        factored.map_err(|e| e.during("factorising the implicit step matrix"))?;
        if plant.contacts.is_empty() || plant.unilateral().is_some() {
            return Ok(());
        }
        // J at the step start: the later stages' evaluations overwrite the workspace's.
        copy_contiguous(&mut self.jacobian, &ws.contact.jacobian);
        self.factor
            .schur_complement(&self.jacobian, &mut self.linv_jt_t, &mut self.schur);
        cholesky_in_place(&mut self.schur).map_err(|i| {
            Error::numerical(
                "implicit step",
                format!("contact constraints are degenerate (pivot {i})"),
            )
        })
    }

    /// The joint stops' stiffness and damping at the step start, on the diagonal:
    /// `g (g k + d)` per joint on its stop (only a plant with stops: without, they stay zero and
    /// unread).
    fn add_stops(&mut self, ws: &Workspace) {
        let g = self.g;
        let terms = &ws.compliance;
        self.stop_stiffness.copy_from_slice(&terms.stop_stiffness);
        self.stop_damping.copy_from_slice(&terms.stop_damping);
        for (j, (k, d)) in self
            .stop_stiffness
            .iter()
            .zip(&self.stop_damping)
            .enumerate()
        {
            self.diagonal[6 + j] += g * mul_add(g, *k, *d);
        }
    }

    /// `M + sum_c g J_c^T (g K_c + D_c) J_c` into `augmented`, with the feet's Jacobians,
    /// stiffness and damping at the step start kept for the solves. The sum keeps the tree's
    /// sparsity: a foot's Jacobian has non-zeros only on the foot's ancestors.
    fn augment_with_contacts(&mut self, plant: &Plant, ws: &Workspace) {
        let g = self.g;
        copy_contiguous(&mut self.jacobian, &ws.contact.jacobian);
        copy_contiguous(&mut self.augmented, &ws.data.mass_matrix);
        let Some(unilateral) = plant.unilateral() else {
            return;
        };
        for c in 0..plant.contacts.len() {
            let (stiffness, damping) = (&mut self.foot_stiffness[c], &mut self.foot_damping[c]);
            foot_matrices(unilateral, ws, c, stiffness, damping);
            let combined = self.foot_stiffness[c] * g + self.foot_damping[c];
            add_foot_to_matrix(
                &self.jacobian,
                6 * c,
                &combined,
                g,
                &mut self.scratch,
                &mut self.augmented,
            );
        }
    }

    /// The step scale `g` it was prepared for (0 before the first).
    pub(crate) fn g(&self) -> f64 {
        self.g
    }

    /// Solves `W k = r` (tangent vectors, size nd) with the matrix of [`WMatrix::prepare`].
    ///
    /// Per elastic joint the motor unknowns are `k_thetadot = a0 + a1 k_sdot`,
    /// `k_theta = r_theta + g k_thetadot`, and the torque perturbation `t0 + t1 k_sdot`; the
    /// velocity part solves `[M~ J^T; J 0] [z; -df] = [B (t0 + t1 r_sdot); c]` with
    /// `c = -(K_d J r_nu + K_p J (r_q + g r_nu)) / (1 + g K_d + g^2 K_p)`; then
    /// `k_nu = r_nu + g z`, `k_q = r_q + g k_nu`.
    pub(crate) fn solve(&mut self, plant: &Plant, r: &DVector<f64>, k: &mut DVector<f64>) {
        let tangent = plant.layout().tangent();
        let g = self.g;
        let r = tangent.split(r.as_slice());
        let k = tangent.split_mut(k.as_mut_slice());
        let actuation = &plant.actuation;
        // z <- B (t0 + t1 r_sdot), keeping a0 per joint in k's thetadot slots for later.
        let z = self.z.as_mut_slice();
        z.fill(0.0);
        for (e, (p, m)) in actuation.elastic.iter().zip(&self.motor).enumerate() {
            let vj = 6 + actuation.elastic_joints[e];
            let (r_s, r_theta, r_thetadot) = (r.dq[vj], r.dtheta[e], r.dthetadot[e]);
            let a0 = m.inv_den * r_thetadot - m.a0_theta * r_theta + m.a0_s * r_s;
            let t0 = p.stiffness * (p.ratio * r_theta - r_s) + m.t0_a0 * a0;
            z[vj] = t0 + m.t1 * r.dnu[vj];
            k.dthetadot[e] = a0;
        }
        self.compliance_rhs(plant, r.dq, r.dnu);
        let z = self.z.as_mut_slice();
        self.factor.solve_lt(z);
        if !plant.contacts.is_empty() && plant.unilateral().is_none() {
            self.solve_constraint(plant, r.dq, r.dnu);
        }
        let z = self.z.as_mut_slice();
        self.factor.solve_l(z);
        for (i, &z_i) in z.iter().enumerate() {
            let k_nu = mul_add(g, z_i, r.dnu[i]);
            k.dnu[i] = k_nu;
            k.dq[i] = mul_add(g, k_nu, r.dq[i]);
        }
        for (e, m) in self.motor.iter().enumerate() {
            let vj = 6 + actuation.elastic_joints[e];
            let k_thetadot = mul_add(m.a1, k.dnu[vj], k.dthetadot[e]);
            k.dthetadot[e] = k_thetadot;
            k.dtheta[e] = mul_add(g, k_thetadot, r.dtheta[e]);
        }
    }

    /// The compliant part of [`WMatrix::solve`]'s right-hand side: with joint stops
    /// `z_j -= k_j (r_q + g r_nu)_j + d_j r_nu_j` and, under unilateral contacts, per foot
    /// `z -= J_c^T (K_c J_c (r_q + g r_nu) + D_c J_c r_nu)` (the forces' change over the stage
    /// that `W`'s augmented matrix does not carry).
    fn compliance_rhs(&mut self, plant: &Plant, r_q: &[f64], r_nu: &[f64]) {
        let g = self.g;
        if plant.joint_stops.is_some() {
            let z = self.z.as_mut_slice();
            let stops = self.stop_stiffness.iter().zip(&self.stop_damping);
            for (j, (k, d)) in stops.enumerate() {
                let v = 6 + j;
                z[v] -= k * mul_add(g, r_nu[v], r_q[v]) + d * r_nu[v];
            }
        }
        if plant.unilateral().is_none() {
            return;
        }
        for c in 0..plant.contacts.len() {
            let force = self.foot_force(c, |v| mul_add(g, r_nu[v], r_q[v]), |v| r_nu[v]);
            let foot = self.jacobian.fixed_rows::<6>(6 * c);
            for (z_v, column) in self.z.as_mut_slice().iter_mut().zip(foot.column_iter()) {
                *z_v -= column.dot(&force);
            }
        }
    }

    /// `K_c J_c dq + D_c J_c dnu` of foot `c` (its wrench's linear response, with the step
    /// start's `J`, stiffness and damping) for the tangent displacement `dq(v)` and velocity
    /// `dnu(v)` given per velocity index.
    fn foot_force(
        &self,
        c: usize,
        dq: impl Fn(usize) -> f64,
        dnu: impl Fn(usize) -> f64,
    ) -> Vector6<f64> {
        // Fixed rows: each column is a `Vector6` view, so the products below allocate nothing.
        let foot = self.jacobian.fixed_rows::<6>(6 * c);
        let (mut displacement, mut velocity) = (Vector6::zeros(), Vector6::zeros());
        for (v, column) in foot.column_iter().enumerate() {
            displacement += column * dq(v);
            velocity += column * dnu(v);
        }
        self.foot_stiffness[c] * displacement + self.foot_damping[c] * velocity
    }

    /// Under unilateral contacts, adds `scale` times the contact wrenches' response to a stage
    /// vector `k` (nd) to `wrenches` (6 per contact): `-(K_c J_c k_q + D_c J_c k_nu)` per foot,
    /// with the step start's `J`, stiffness and damping. `f(x) + g Jf k` is what a W-method's
    /// stage integrates, so a stage's effective wrench is its evaluated one plus `g` times
    /// this. Nothing under bilateral contacts.
    pub(crate) fn add_contact_response(
        &self,
        plant: &Plant,
        k: &DVector<f64>,
        scale: f64,
        wrenches: &mut DVector<f64>,
    ) {
        if plant.unilateral().is_none() {
            return;
        }
        let k = plant.layout().tangent().split(k.as_slice());
        for c in 0..plant.contacts.len() {
            let response = self.foot_force(c, |v| k.dq[v], |v| k.dnu[v]);
            let mut rows = wrenches.fixed_rows_mut::<6>(6 * c);
            rows -= response * scale;
        }
    }

    /// The contact part of [`WMatrix::solve`]: `z += Y~ S~^-1 (c - Y~^T z)` with
    /// `c = -J (K_d r_nu + K_p (r_q + g r_nu)) / (1 + g K_d + g^2 K_p)`, the velocity
    /// combination formed first so that `J` is applied once (gemv over its columns).
    fn solve_constraint(&mut self, plant: &Plant, r_q: &[f64], r_nu: &[f64]) {
        let g = self.g;
        let kp = plant.baumgarte_kp;
        let kd = plant.baumgarte_kd;
        let scale = 1.0 / (1.0 + g * kd + g * g * kp);
        let combination = self.combination.as_mut_slice();
        for ((c, &q_i), &nu_i) in combination.iter_mut().zip(r_q).zip(r_nu) {
            *c = mul_add(kd, nu_i, kp * mul_add(g, nu_i, q_i));
        }
        let rhs = self.constraint.as_mut_slice();
        let z = self.z.as_mut_slice();
        gemv_few_rows(rhs, -scale, &self.jacobian, combination, 0.0);
        gemv_few_rows(rhs, -1.0, &self.linv_jt_t, z, 1.0);
        cholesky_solve_in_place(&self.schur, rhs);
        gemv_tr_few_rows(z, 1.0, &self.linv_jt_t, rhs, 1.0);
    }
}
