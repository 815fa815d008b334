//! The cross-check of the active set against Clarabel (for tests; off by default and then not
//! on the per-tick path): with [`super::WrenchQp::cross_check`] on, every problem the active
//! set solves is also solved by Clarabel, and the differences and both solutions' constraint
//! violations are kept in [`QpAgreement`].

use super::active_set::ActiveSetQp;
use super::clarabel::ClarabelQp;
use super::problem::SoleFrameProblem;
use nalgebra::DVector;

/// The agreement of the active set with Clarabel over the ticks of a cross-check
/// ([`super::WrenchQp::cross_check`]). Differences are Euclidean norms of force or moment
/// 3-vectors (frame independent); violations are in the constraint rows' units (N for the rows
/// of [`super::ContactConstraints::sole_rows`], whose normal-force coefficient is 1 or a
/// length).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QpAgreement {
    /// Ticks compared.
    pub ticks: usize,
    /// Ticks where Clarabel failed (not compared).
    pub reference_failures: usize,
    /// Largest difference between the active set's and Clarabel's force or moment [N, Nm].
    pub max_wrench_difference: f64,
    /// Largest force or moment norm of Clarabel's solutions (the scale of the differences).
    pub max_wrench: f64,
    /// Largest `|f_active - f_clarabel|_2 / sqrt(1 + |J_clarabel|)` (whole vectors, `J` the
    /// objective `0.5 f^T P f + c^T f`): Clarabel stops at a duality gap of about
    /// `eps (1 + |J|)`, and in a QP whose Hessian is at least `lambda_min I` a feasible point
    /// that much above the optimum is within `sqrt(2 eps (1 + |J|) / lambda_min)` of it, so
    /// this ratio is bounded by `sqrt(2 eps / lambda_min)`.
    pub max_scaled_difference: f64,
    /// Largest `(J_active - J_clarabel) / (1 + |J_clarabel|)`: about rounding when both are
    /// optimal; Clarabel's point, feasible only to its tolerance, may lie below.
    pub max_objective_excess: f64,
    /// Largest KKT stationarity residual of the active set's solution with its multipliers
    /// ([`ActiveSetQp::stationarity_residual`], relative): its own optimality certificate.
    pub max_stationarity_residual: f64,
    /// Largest violation `max(C w - b, 0)` of the active set's wrenches.
    pub max_inequality_violation: f64,
    /// The same for Clarabel's wrenches (its feasibility tolerance at work).
    pub reference_max_inequality_violation: f64,
    /// Largest `|A f - b|_inf` of the active set's wrenches.
    pub max_equality_residual: f64,
    /// Largest `|b|_inf` (the scale of the residuals).
    pub max_equality_target: f64,
    /// Ticks whose active-set optimum has at least one active inequality.
    pub ticks_with_active_inequalities: usize,
    /// Most inequalities active at one optimum.
    pub max_active_inequalities: usize,
}

/// One tick's figures of the cross-check (see [`QpAgreement`]).
struct TickComparison {
    difference: f64,
    scale: f64,
    scaled_difference: f64,
    objective_excess: f64,
    stationarity: f64,
    violation: f64,
    reference_violation: f64,
    residual: f64,
    target: f64,
    active: usize,
}

impl QpAgreement {
    /// Adds one compared tick.
    fn add(&mut self, tick: &TickComparison) {
        self.ticks += 1;
        self.max_wrench_difference = self.max_wrench_difference.max(tick.difference);
        self.max_wrench = self.max_wrench.max(tick.scale);
        self.max_scaled_difference = self.max_scaled_difference.max(tick.scaled_difference);
        self.max_objective_excess = if self.ticks == 1 {
            tick.objective_excess
        } else {
            self.max_objective_excess.max(tick.objective_excess)
        };
        self.max_stationarity_residual = self.max_stationarity_residual.max(tick.stationarity);
        self.max_inequality_violation = self.max_inequality_violation.max(tick.violation);
        self.reference_max_inequality_violation = self
            .reference_max_inequality_violation
            .max(tick.reference_violation);
        self.max_equality_residual = self.max_equality_residual.max(tick.residual);
        self.max_equality_target = self.max_equality_target.max(tick.target);
        self.ticks_with_active_inequalities += usize::from(tick.active > 0);
        self.max_active_inequalities = self.max_active_inequalities.max(tick.active);
    }
}

/// The cross-check's buffers: Clarabel's sole-frame solution (k) and scratch (k).
pub(super) struct CrossCheck {
    reference: DVector<f64>,
    scratch: DVector<f64>,
}

/// What the cross-check compares: the problem, its solvers, and the active set's result.
pub(super) struct Compared<'a> {
    pub(super) problem: &'a SoleFrameProblem,
    pub(super) b_eq: Option<&'a DVector<f64>>,
    pub(super) active_set: &'a ActiveSetQp,
    pub(super) clarabel: &'a mut ClarabelQp,
    /// The active set's sole-frame solution and its number of active inequalities.
    pub(super) checked: &'a DVector<f64>,
    pub(super) active: usize,
}

impl CrossCheck {
    /// Buffers for `k` variables.
    pub(super) fn new(k: usize) -> Self {
        Self {
            reference: DVector::zeros(k),
            scratch: DVector::zeros(k),
        }
    }

    /// Clarabel on the same sole-frame problem, its differences from the active set's
    /// solution and both solutions' constraint violations into `agreement` (a Clarabel
    /// failure is counted, not compared).
    pub(super) fn compare(&mut self, compared: Compared<'_>, agreement: &mut QpAgreement) {
        let Compared {
            problem,
            b_eq,
            active_set,
            clarabel,
            checked,
            active,
        } = compared;
        if clarabel.solve(problem, b_eq, &mut self.reference).is_err() {
            agreement.reference_failures += 1;
            return;
        }
        let reference = &self.reference;
        let (difference, scale) = wrench_difference(checked, reference);
        let objective_reference = problem.objective(reference);
        let objective = problem.objective(checked);
        let (residual, target) = match b_eq {
            Some(b) => {
                self.scratch.rows_mut(0, b.len()).copy_from(b);
                let mut residual = self.scratch.rows_mut(0, b.len());
                residual.gemv(1.0, &problem.equality, checked, -1.0);
                (residual.amax(), b.amax())
            }
            None => (0.0, 0.0),
        };
        let equality = b_eq.map(|_| &problem.equality);
        let stationarity = active_set.stationarity_residual(
            &problem.hessian,
            &problem.gradient,
            equality,
            checked,
            &mut self.scratch,
        );
        let root = (1.0 + objective_reference.abs()).sqrt();
        agreement.add(&TickComparison {
            difference,
            scale,
            scaled_difference: distance(checked, reference) / root,
            objective_excess: (objective - objective_reference) / (root * root),
            stationarity,
            violation: problem.inequality_violation(checked),
            reference_violation: problem.inequality_violation(reference),
            residual,
            target,
            active,
        });
    }
}

/// `|a - b|_2`.
fn distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// The largest Euclidean norm of the difference of two stacked wrenches' force or moment
/// 3-vectors, and the largest such norm of `reference`.
fn wrench_difference(solution: &DVector<f64>, reference: &DVector<f64>) -> (f64, f64) {
    let (mut difference, mut scale): (f64, f64) = (0.0, 0.0);
    for start in (0..solution.len()).step_by(3) {
        let a = solution.fixed_rows::<3>(start);
        let b = reference.fixed_rows::<3>(start);
        difference = difference.max((a - b).norm());
        scale = scale.max(b.norm());
    }
    (difference, scale)
}
