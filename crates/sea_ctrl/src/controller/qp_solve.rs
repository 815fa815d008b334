//! The contact-wrench QP of a tick (inputTorquesSOT / inputTorquesSOTu, subject to
//! frictionCones): one foot `min |A f - b|^2`, two feet `min |tau(f)|^2` s.t. `A f = b` (the
//! objective and the minimiser without inequalities built here, solved by [`crate::qp`]); two
//! feet, when `A f = b` is infeasible and [`MomentumRelaxation::WhenInfeasible`] is set, the
//! relaxed momentum task (the closest momentum rate the contacts can produce).

use super::settings::MomentumRelaxation;
use super::MomentumController;
use crate::qp::{
    add_moment_regularization, momentum_tracking_objective, relaxed_momentum_objective,
    torque_norm_objective, QpStatus, RelaxedMomentumWeights,
};
use nalgebra::DVector;

impl MomentumController {
    /// The QP of this tick (inputTorquesSOT / inputTorquesSOTu): builds the objective, the
    /// minimiser without inequalities, and solves into `wrenches` (k). Two feet whose `Lambda`
    /// has a lower rank than `J` (legs of 5 joints) do not take the paper's `A f = b`: eq:torques
    /// is then solvable only for wrenches on a hyperplane, on which `A f` cannot follow one
    /// momentum-rate direction, and wrenches off it (what `A f = b` picks) are not what the
    /// torques produce: the run diverged within 0.2 s. They take
    /// [`crate::redundant_contacts`]'s equalities (the momentum task in the directions the
    /// contacts can move, and the wrenches the joints can produce; docs/findings/robots.md).
    pub(super) fn solve_qp(&mut self, wrenches: &mut DVector<f64>) -> QpStatus {
        if let Some(stance) = self.stance_contact() {
            return self.solve_single_support(stance, wrenches);
        }
        if let Some(weight) = self.double_support_momentum_weight() {
            return self.solve_double_support_least_squares(weight, wrenches);
        }
        let terms = &self.terms;
        let reg = self.settings.tuning.qp_regularization;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        let two_feet = self.contact_frames.len() > 1;
        // The paper's `A f = b`, or with a redundant contact set the momentum task the
        // contacts can follow and the wrenches the joints can produce.
        let (equality_map, equality_target) = match &self.redundant {
            Some(redundant) => (&redundant.equality, &redundant.target),
            None => (&terms.momentum_map, &terms.momentum_target),
        };
        let found = if two_feet {
            torque_norm_objective(&terms.sigma, &terms.tau_bias, reg, hessian, gradient);
            add_moment_regularization(hessian, self.settings.tuning.qp_moment_regularization);
            if let Some(walking) = &self.walking {
                walking.add_share_penalties(hessian);
            }
            self.minimizer.equality_constrained(
                hessian,
                gradient,
                equality_map,
                equality_target,
                &mut self.unconstrained,
            )
        } else {
            let (a, b) = (&terms.momentum_map, &terms.momentum_target);
            momentum_tracking_objective(a, b, reg, hessian, gradient);
            self.minimizer
                .unconstrained(hessian, gradient, &mut self.unconstrained)
        };
        let equality = two_feet.then_some((equality_map, equality_target));
        let status = self.qp.solve(
            hessian,
            gradient,
            equality,
            &terms.contact_rotations,
            found.then_some(&self.unconstrained),
            wrenches,
        );
        let relax = self.settings.tuning.momentum_relaxation == MomentumRelaxation::WhenInfeasible;
        match status {
            QpStatus::Fallback(_) if two_feet && relax => {
                self.solve_relaxed(wrenches).unwrap_or(status)
            }
            _ => status,
        }
    }

    /// The relaxed momentum task of an infeasible two-feet tick into `wrenches` (k):
    /// `MomentumRelaxed`, or `None` (wrenches untouched) when it fails too.
    fn solve_relaxed(&mut self, wrenches: &mut DVector<f64>) -> Option<QpStatus> {
        let terms = &self.terms;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        relaxed_momentum_objective(
            (&terms.momentum_map, &terms.momentum_target),
            (&terms.sigma, &terms.tau_bias),
            RelaxedMomentumWeights {
                angular: self.settings.tuning.relaxed_angular_weight,
                ..RelaxedMomentumWeights::default()
            },
            self.settings.tuning.qp_regularization,
            hessian,
            gradient,
        );
        let relaxed = &mut self.relaxed_wrenches;
        let status = self.relaxed_qp.solve(
            hessian,
            gradient,
            None,
            &terms.contact_rotations,
            None,
            relaxed,
        );
        let solved = status == QpStatus::Solved;
        if solved {
            wrenches.copy_from(relaxed);
            self.relaxations += 1;
        }
        solved.then_some(QpStatus::MomentumRelaxed)
    }

    /// Walking, double support with `walking.double_support_momentum_weight` = `weight` > 0:
    /// the momentum task in least squares instead of the paper's equality, `min |tau(f)|^2 +
    /// w |A f - b|^2` (plus the share penalties), `w` = `weight` times the torque Hessian's
    /// mean diagonal, solved by the two-feet QP without equalities into `wrenches` (k).
    fn solve_double_support_least_squares(
        &mut self,
        weight: f64,
        wrenches: &mut DVector<f64>,
    ) -> QpStatus {
        let terms = &self.terms;
        let reg = self.settings.tuning.qp_regularization;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        torque_norm_objective(&terms.sigma, &terms.tau_bias, reg, hessian, gradient);
        add_moment_regularization(hessian, self.settings.tuning.qp_moment_regularization);
        let scale = weight * hessian.trace() / hessian.nrows() as f64;
        // The share penalties on the torque objective's scale, as with the equality.
        if let Some(walking) = &self.walking {
            walking.add_share_penalties(hessian);
        }
        let (a, b) = (&terms.momentum_map, &terms.momentum_target);
        hessian.gemm_tr(2.0 * scale, a, a, 1.0);
        gradient.gemv_tr(-2.0 * scale, a, b, 1.0);
        let found = self
            .minimizer
            .unconstrained(hessian, gradient, &mut self.unconstrained);
        let walking = self
            .walking
            .as_mut()
            .expect("double support in least squares only when walking");
        walking.least_squares_qp.solve(
            hessian,
            gradient,
            None,
            &terms.contact_rotations,
            found.then_some(&self.unconstrained),
            wrenches,
        )
    }
}
