//! The momentum task (paper section "Momentum control"): the rate of change of the centroidal
//! momentum as a function of the contact wrenches (hDot), its reference (eq:dotH_f) with the
//! integral term (eq:IhTilde), and the contact-constrained momentum Jacobian (eqn:jacobian)
//! that the integral term uses.
//!
//! Sizes and frames: the centroidal momentum `H = [m pdot_com; L_com]` (6, world axes, angular
//! momentum about the CoM); the stacked contact wrenches `f` (6 per contact, `[force; moment
//! about the contact frame's origin]`, world axes); positions in world [m]; `n` joints.

use crate::error::{Error, Result};
use crate::references::ComSample;
use nalgebra::{DMatrix, DVector, Matrix6, Vector3, Vector6};
use sea_dyn::dense::gemm_small;
use sea_dyn::spatial::{quaternion_from_rotation, skew, Pose};
use sea_dyn::{Data, FrameId, Model};

/// The momentum map `A` (6 x 6 n_contacts) of paper hDot, `Hdot(f) = A f + [m g; 0]`, with
/// only its constant identity blocks set: `A_k = [[I, 0], [skew(p_k - p_com), I]]`, the skew
/// blocks are written each tick by [`set_momentum_map_contact`]. (`A` is the paper's `J_b^T`
/// in the coordinates of centrTrans.)
pub fn momentum_map_identity_blocks(n_contacts: usize) -> DMatrix<f64> {
    let mut momentum_map = DMatrix::zeros(6, 6 * n_contacts);
    for c in 0..n_contacts {
        momentum_map
            .view_mut((0, 6 * c), (6, 6))
            .fill_with_identity();
    }
    momentum_map
}

/// Paper hDot, contact `contact`'s block of `A`: the moment of its force about the CoM,
/// `skew(p_contact - p_com)` (world axes, positions [m]); the other blocks of `A_k` are
/// constant.
pub fn set_momentum_map_contact(
    momentum_map: &mut DMatrix<f64>,
    contact: usize,
    p_contact_world: &Vector3<f64>,
    p_com_world: &Vector3<f64>,
) {
    momentum_map
        .fixed_view_mut::<3, 3>(3, 6 * contact)
        .copy_from(&skew(&(p_contact_world - p_com_world)));
}

/// Paper hDot: the rate of change of the centroidal momentum produced by the contact wrenches
/// `f` (6 n_contacts) and gravity, `Hdot(f) = A f + [m g; 0]` (`g` the gravity vector, world,
/// so `m g = -m 9.81 e_3`) [N, Nm].
pub fn momentum_rate(
    momentum_map: &DMatrix<f64>,
    wrenches: &DVector<f64>,
    mass: f64,
    gravity: &Vector3<f64>,
) -> Vector6<f64> {
    let mut rate = Vector6::zeros();
    rate.gemv(1.0, momentum_map, wrenches, 0.0);
    rate.fixed_rows_mut::<3>(0).axpy(mass, gravity, 1.0);
    rate
}

/// The right-hand side `b` of the momentum equality `A f = b` of inputTorquesSOT: `Hdot(f) =
/// Hdot*` (hDot) solved for `A f`, `b = Hdot* - [m g; 0]` (6, world axes).
pub fn momentum_equality_target(
    momentum_rate_star: &Vector6<f64>,
    mass: f64,
    gravity: &Vector3<f64>,
) -> Vector6<f64> {
    let weight = gravity * mass;
    Vector6::from_fn(|r, _| momentum_rate_star[r] - if r < 3 { weight[r] } else { 0.0 })
}

/// The desired momentum and its rate from the CoM reference (paper hDotDes, `H^d`, `Hdot^d`):
/// `H^d = [m pdot_com_d; 0]`, `Hdot^d = [m pddot_com_d; 0]` (world axes).
pub fn desired_momentum(mass: f64, reference: &ComSample) -> (Vector6<f64>, Vector6<f64>) {
    let velocity = reference.velocity * mass;
    let mut momentum = Vector6::zeros();
    let mut rate = Vector6::zeros();
    for r in 0..3 {
        momentum[r] = velocity[r];
        rate[r] = mass * reference.acceleration[r];
    }
    (momentum, rate)
}

/// Paper eq:IhTilde, the integral of the momentum error `I_Htilde` (6): integrating
/// `[J_G^L(s); J_G^omega(s_d)] sdot` gives `m (p_com - p_com_d)` for the linear part (CoM
/// positions world [m]) and `J_G^omega(s_d) (s - s_d)` for the angular part, the integration
/// constants chosen so that both vanish at the reference. `jg_angular` is `J_G^omega(s_d)`
/// (3 x n, from [`MomentumJacobian`]), `posture_error` is `s - s_d` (n) [rad].
pub fn momentum_integral_error(
    mass: f64,
    p_com_world: &Vector3<f64>,
    p_com_desired_world: &Vector3<f64>,
    jg_angular: &DMatrix<f64>,
    posture_error: &[f64],
) -> Vector6<f64> {
    let linear = (p_com_world - p_com_desired_world) * mass;
    let angular = Vector3::from_fn(|r, _| {
        let row = jg_angular.row(r);
        row.iter().zip(posture_error).map(|(a, b)| a * b).sum()
    });
    Vector6::new(
        linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
    )
}

/// Paper eq:dotH_f, the momentum rate reference `Hdot* = Hdot^d - K_p Htilde - K_i I_Htilde`
/// (6, world axes) with diagonal gains `K_p`, `K_i` (linear rows first), the momentum error
/// `Htilde = H - H^d` and the integral error `I_Htilde` (eq:IhTilde).
pub fn momentum_rate_star(
    desired_rate: &Vector6<f64>,
    momentum_error: &Vector6<f64>,
    integral_error: &Vector6<f64>,
    proportional: &[f64; 6],
    integral: &[f64; 6],
) -> Vector6<f64> {
    Vector6::from_fn(|r, _| {
        desired_rate[r] - proportional[r] * momentum_error[r] - integral[r] * integral_error[r]
    })
}

/// Paper eqn:jacobian, the angular rows `J_G^omega(s_d)` (3 x n) of the momentum Jacobian on
/// the contact constraints, `J_G = A_Gj - A_Gb J_b^+ J_j` (6 x n; `-M_b J_b^+ J_j` in the
/// coordinates of centrTrans, where `A_Gj = 0`), evaluated at the joint positions `s_d` with
/// the first contact at its reference placement. Holds its buffers; recomputes only when `s_d`
/// changes.
pub struct MomentumJacobian {
    /// `J_G^omega(s_d)` (3 x n).
    pub angular: DMatrix<f64>,
    /// `s_d` of [`Self::angular`] (n); meaningless until `valid`.
    posture: Vec<f64>,
    valid: bool,
    /// Configuration at `s_d` (nq).
    q: Vec<f64>,
    /// The model's neutral configuration (nq): the base part seeds [`Self::place_base`].
    neutral: Vec<f64>,
    /// `A_G(q)` (6 x nv).
    a_g: DMatrix<f64>,
    /// Stacked contact Jacobians `J = [J_b J_j]` (k x nv).
    jacobian: DMatrix<f64>,
    /// `J_b^T` (6 x k).
    j_b_t: DMatrix<f64>,
    /// `J_j` (k x n).
    j_j: DMatrix<f64>,
    /// `J_b^T J_b` (6 x 6), then its inverse.
    gram: DMatrix<f64>,
    /// `J_b^+ = (J_b^T J_b)^-1 J_b^T` (6 x k).
    j_b_pinv: DMatrix<f64>,
    /// `A_Gb J_b^+` (6 x k).
    coupling: DMatrix<f64>,
    /// `A_Gb J_b^+ J_j` (6 x n).
    product: DMatrix<f64>,
}

impl MomentumJacobian {
    /// Buffers for `model` and `k` contact rows (6 per contact).
    pub fn new(model: &Model, k: usize) -> Self {
        let (nv, n) = (model.nv(), model.n_joints());
        Self {
            angular: DMatrix::zeros(3, n),
            posture: vec![0.0; n],
            valid: false,
            q: model.neutral(),
            neutral: model.neutral(),
            a_g: DMatrix::zeros(6, nv),
            jacobian: DMatrix::zeros(k, nv),
            j_b_t: DMatrix::zeros(6, k),
            j_j: DMatrix::zeros(k, n),
            gram: DMatrix::zeros(6, 6),
            j_b_pinv: DMatrix::zeros(6, k),
            coupling: DMatrix::zeros(6, k),
            product: DMatrix::zeros(6, n),
        }
    }

    /// `J_G^omega(s_d)` into [`Self::angular`] for the joint positions `s_desired` (n), the
    /// contact frames `contact_frames` and the reference `world_H_contact` of the first one;
    /// `data` is scratch. Does nothing when `s_desired` is the last one.
    pub fn update(
        &mut self,
        model: &Model,
        data: &mut Data,
        contact_frames: &[FrameId],
        world_h_first_contact: &Pose,
        s_desired: &[f64],
    ) -> Result<()> {
        if self.valid && self.posture == s_desired {
            return Ok(());
        }
        self.place_base(
            model,
            data,
            contact_frames[0],
            world_h_first_contact,
            s_desired,
        );
        self.a_g
            .copy_from(sea_dyn::centroidal_momentum_matrix(model, data, &self.q));
        for (c, &frame) in contact_frames.iter().enumerate() {
            let j = sea_dyn::frame_jacobian(model, data, &self.q, frame);
            self.jacobian.rows_mut(6 * c, 6).copy_from(j);
        }
        let n = model.n_joints();
        self.j_b_t.tr_copy_from(&self.jacobian.columns(0, 6));
        self.j_j.copy_from(&self.jacobian.columns(6, n));
        self.gram.gemm_tr(
            1.0,
            &self.jacobian.columns(0, 6),
            &self.jacobian.columns(0, 6),
            0.0,
        );
        let gram: Matrix6<f64> = self.gram.fixed_view::<6, 6>(0, 0).into_owned();
        let inverse = gram.try_inverse().ok_or_else(|| {
            Error::from(sea_dyn::Error::numerical(
                "J_G^omega: inverting J_b^T J_b of the contact Jacobian",
                "the base block of the contact Jacobian has no full column rank",
            ))
        })?;
        self.gram.copy_from(&inverse);
        let (gram, j_b_t) = (self.gram.as_view(), self.j_b_t.as_view());
        gemm_small(&mut self.j_b_pinv, 1.0, gram, j_b_t, 0.0);
        let (a_gb, j_b_pinv) = (self.a_g.columns(0, 6), self.j_b_pinv.as_view());
        gemm_small(&mut self.coupling, 1.0, a_gb, j_b_pinv, 0.0);
        let (coupling, j_j) = (self.coupling.as_view(), self.j_j.as_view());
        gemm_small(&mut self.product, 1.0, coupling, j_j, 0.0);
        for r in 0..3 {
            for j in 0..n {
                self.angular[(r, j)] = self.a_g[(3 + r, 6 + j)] - self.product[(3 + r, j)];
            }
        }
        self.posture.copy_from_slice(s_desired);
        self.valid = true;
        Ok(())
    }

    /// The configuration with joints `s_desired` whose base puts `first_contact` at
    /// `world_h_first_contact`, into `self.q`.
    fn place_base(
        &mut self,
        model: &Model,
        data: &mut Data,
        first_contact: FrameId,
        world_h_first_contact: &Pose,
        s_desired: &[f64],
    ) {
        self.q.copy_from_slice(&self.neutral);
        self.q[7..].copy_from_slice(s_desired);
        sea_dyn::forward_kinematics(model, data, &self.q);
        let base_h_contact = sea_dyn::frame_placement(model, data, first_contact);
        let world_h_base = world_h_first_contact.compose(&base_h_contact.inverse());
        let quaternion = quaternion_from_rotation(&world_h_base.rotation);
        self.q[..3].copy_from_slice(world_h_base.translation.as_slice());
        self.q[3..7].copy_from_slice(&quaternion);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sea_dyn::sample::Lcg;

    /// hDot with two contacts: `momentum_rate` is the net wrench about the CoM plus gravity,
    /// `[sum F_k + m g; sum (n_k + (p_k - p_com) x F_k)]`, and the QP's equality `A f = b` with
    /// `b` from `momentum_equality_target` makes it `Hdot*`.
    #[test]
    fn momentum_rate_is_the_net_wrench_about_the_com_plus_gravity() {
        let mut rng = Lcg::new(3);
        let mut random_vector = || Vector3::new(rng.next_signed(), rng.next_signed(), 0.5);
        let (p_com, gravity, mass) = (random_vector(), Vector3::new(0.0, 0.0, -9.81), 33.0);
        let contacts = [random_vector(), random_vector()];
        let mut momentum_map = momentum_map_identity_blocks(2);
        for (c, p_contact) in contacts.iter().enumerate() {
            set_momentum_map_contact(&mut momentum_map, c, p_contact, &p_com);
        }
        let wrenches = DVector::from_fn(12, |i, _| 10.0 * (i as f64 - 5.5));
        let rate = momentum_rate(&momentum_map, &wrenches, mass, &gravity);
        let mut expected = Vector6::zeros();
        for (c, p_contact) in contacts.iter().enumerate() {
            let force = wrenches.fixed_rows::<3>(6 * c).into_owned();
            let moment = wrenches.fixed_rows::<3>(6 * c + 3).into_owned();
            let angular = moment + (p_contact - p_com).cross(&force);
            expected += Vector6::new(force.x, force.y, force.z, angular.x, angular.y, angular.z);
        }
        expected.fixed_rows_mut::<3>(0).axpy(mass, &gravity, 1.0);
        assert!((rate - expected).amax() < 1e-12, "{rate} != {expected}");
        // A f = b(Hdot*) gives Hdot(f) = Hdot*.
        let rate_star = Vector6::new(1.0, -2.0, 3.0, 0.1, 0.2, -0.3);
        let target = momentum_equality_target(&rate_star, mass, &gravity);
        let pseudo_inverse = momentum_map.clone().pseudo_inverse(1e-12).unwrap();
        let realising = pseudo_inverse * DVector::from_column_slice(target.as_slice());
        let realised = momentum_rate(&momentum_map, &realising, mass, &gravity);
        assert!(
            (realised - rate_star).amax() < 1e-9,
            "{realised} != {rate_star}"
        );
    }
}
