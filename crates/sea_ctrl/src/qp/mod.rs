//! The contact-wrench QP, paper inputTorquesSOT (rigid joints: `min |tau*(f)|^2`, label
//! inputTorquesSOTMinTau) and inputTorquesSOTu (SEA: `min |beta*(f)|^2`, label
//! inputTorquesMinVel; the same problem after the substitutions of newJointDynamics).
//!
//! Variables: the stacked contact wrenches `f` (6 per contact, `[force; moment about the sole
//! origin]`, world axes). Objective `0.5 f^T P f + c^T f`: two feet, [`torque_norm_objective`]
//! `|tau(f)|^2` with `tau(f) = tau_bias + Sigma f` from the torque map; one foot (where `A f =
//! b` fixes `f`), [`momentum_tracking_objective`] `|A f - b|^2`; both plus a regulariser.
//! Constraints: the momentum task `Hdot(f) = Hdot*` as the equalities `A f = b` (two feet;
//! see [`crate::momentum`]) and, per contact, the contact constraints `C f <= b` (label
//! frictionCones, [`ContactConstraints::sole_rows`]) in its sole frame (`w_s =
//! blockdiag(R^T, R^T) w`): a linearised friction cone with `facets` faces inscribed in the
//! cone of coefficient `mu` (`cos(phi_k) F_x + sin(phi_k) F_y <= mu cos(pi / facets) F_z`), a
//! minimum normal force, torsional friction `|n_z| <= mu_t F_z`, and the centre of pressure
//! `(-n_y / F_z, n_x / F_z)` inside the foot rectangle.
//!
//! Order of a solve ([`WrenchQp::solve`]):
//!
//! 1. (when [`WrenchQp::unconstrained_first`] is set) the caller's minimiser without the
//!    inequalities ([`Minimizer`], file `minimiser.rs`) is checked against them: if it
//!    satisfies every one, it is the QP's optimum (a convex problem whose KKT conditions hold
//!    with zero inequality multipliers). While balancing, the contacts are mostly far from
//!    their friction, CoP and normal-force limits, and this check costs a few hundred flops;
//! 2. (when [`WrenchQp::solver`] is [`QpSolver::ActiveSet`], the default) the dense
//!    Goldfarb-Idnani dual active-set method of [`active_set`] on the problem in the sole-frame
//!    variables `w = T^T f`, `T = blockdiag(R_k, R_k)` (file `problem.rs`), where the contact
//!    rows are constant: exact up to rounding, allocation-free, a few microseconds for 12
//!    variables;
//! 3. Clarabel (interior point; file `clarabel.rs`), the reference: when selected, or when the
//!    active set fails (iteration limit, infeasible, numerically singular);
//! 4. the unconstrained solution with a `Fallback` status when Clarabel fails too (the
//!    controller may then solve the relaxed momentum task, [`relaxed_momentum_objective`], on a
//!    second `WrenchQp` without equality rows: `MomentumRelaxed`).
//!
//! [`WrenchQp::counters`] counts the solves by path ([`QpCounters`]). With
//! [`WrenchQp::cross_check`] on, every problem the active set solves is also solved by Clarabel
//! and the agreement kept in [`WrenchQp::agreement`] (file `cross_check.rs`; for tests).

pub mod active_set;
mod clarabel;
mod cross_check;
mod minimiser;
mod problem;

pub use self::clarabel::CLARABEL_TOLERANCE;
pub use active_set::{ActiveSetError, ActiveSetQp};
pub use cross_check::QpAgreement;
pub use minimiser::Minimizer;
#[cfg(feature = "serde")]
pub use problem::CopMargin;
pub use problem::{
    add_moment_regularization, momentum_tracking_objective, relaxed_momentum_objective,
    torque_norm_objective, ContactConstraints, RelaxedMomentumWeights, MAX_FRICTION_FACETS,
    MIN_FRICTION_FACETS,
};

use self::clarabel::ClarabelQp;
use cross_check::{Compared, CrossCheck};
use nalgebra::{DMatrix, DVector, Matrix3};
use problem::SoleFrameProblem;

/// Which solver solves the wrench QP when the minimiser without inequalities is not taken;
/// with the `serde` feature, named as [`QpSolver::name`] says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum QpSolver {
    /// The dense Goldfarb-Idnani active-set method ([`active_set`]), Clarabel as fallback.
    #[default]
    ActiveSet,
    /// Clarabel (interior point) on every solve.
    Clarabel,
}

impl QpSolver {
    /// Every solver, in the order of [`Self::name`]'s documentation.
    pub const ALL: [QpSolver; 2] = [QpSolver::ActiveSet, QpSolver::Clarabel];

    /// The setting's name: "active_set" or "clarabel".
    pub fn name(self) -> &'static str {
        match self {
            QpSolver::ActiveSet => "active_set",
            QpSolver::Clarabel => "clarabel",
        }
    }
}

/// How a tick's QP ended.
#[derive(Clone, Debug, PartialEq)]
pub enum QpStatus {
    /// Solved: the minimiser without inequalities was feasible, or the active set or Clarabel
    /// solved (Clarabel: `Solved` or `AlmostSolved`).
    Solved,
    /// Two feet: the QP with the momentum equality was infeasible (every solver failed) and the
    /// relaxed momentum task (the closest momentum rate the contacts can produce,
    /// [`relaxed_momentum_objective`]) was solved instead; set by the controller.
    MomentumRelaxed,
    /// Every solver failed; the unconstrained solution was used (the reason: Clarabel's).
    Fallback(String),
}

/// The counters of a [`WrenchQp`]: how many solves took each path of [`WrenchQp::solve`],
/// and how many failed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QpCounters {
    /// The minimiser without inequalities was feasible, hence optimal.
    pub unconstrained: usize,
    /// Solved by the active-set method.
    pub active_set: usize,
    /// Solved (or attempted) by Clarabel, including the active set's fallbacks.
    pub clarabel: usize,
    /// Active-set solves that failed and went to Clarabel.
    pub active_set_failures: usize,
    /// Solves where Clarabel failed too and the unconstrained solution was used.
    pub fallbacks: usize,
}

impl std::ops::Add for QpCounters {
    type Output = Self;

    /// The counts of two QPs' solves together (path by path).
    fn add(self, other: Self) -> Self {
        Self {
            unconstrained: self.unconstrained + other.unconstrained,
            active_set: self.active_set + other.active_set,
            clarabel: self.clarabel + other.clarabel,
            active_set_failures: self.active_set_failures + other.active_set_failures,
            fallbacks: self.fallbacks + other.fallbacks,
        }
    }
}

/// The contact-wrench QP for a fixed number of contacts and equality rows (see the module
/// doc), with every buffer allocated in [`WrenchQp::new`].
pub struct WrenchQp {
    /// The problem of the current solve in the sole-frame variables.
    problem: SoleFrameProblem,
    /// The sole-frame solution `w` (k).
    solution_sole: DVector<f64>,
    /// The active-set solver, its inequalities the sole rows of every contact.
    active_set: ActiveSetQp,
    /// Clarabel, the reference and fallback.
    clarabel: ClarabelQp,
    counters: QpCounters,
    last_active_set_failure: Option<ActiveSetError>,
    /// Accept the minimiser without inequalities when it satisfies them (see the module doc).
    pub unconstrained_first: bool,
    /// Which solver solves when the minimiser without inequalities is not taken.
    pub solver: QpSolver,
    /// Also solve every active-set problem with Clarabel and record the agreement (for tests).
    pub cross_check: bool,
    /// The cross-check's figures so far.
    pub agreement: QpAgreement,
    cross_check_buffers: CrossCheck,
}

impl WrenchQp {
    /// A QP for `n_contacts` wrenches and `n_equalities` equality rows (0 or 6).
    pub fn new(n_contacts: usize, n_equalities: usize, constraints: &ContactConstraints) -> Self {
        let problem = SoleFrameProblem::new(n_contacts, n_equalities, constraints);
        let n = problem.n_variables();
        let (block_c, block_b) = problem.block_diagonal_rows();
        let mut active_set = ActiveSetQp::new(n, n_equalities, block_c.nrows());
        active_set.set_inequalities(&block_c, &block_b);
        Self {
            clarabel: ClarabelQp::new(&problem),
            problem,
            solution_sole: DVector::zeros(n),
            active_set,
            counters: QpCounters::default(),
            last_active_set_failure: None,
            unconstrained_first: true,
            solver: QpSolver::default(),
            cross_check: false,
            agreement: QpAgreement::default(),
            cross_check_buffers: CrossCheck::new(n),
        }
    }

    /// The solves so far by path, and the failures.
    pub fn counters(&self) -> QpCounters {
        self.counters
    }

    /// Why the last failed active-set solve failed (`None` if none failed).
    pub fn last_active_set_failure(&self) -> Option<ActiveSetError> {
        self.last_active_set_failure
    }

    /// Number of variables `6 n_contacts`.
    pub fn n_variables(&self) -> usize {
        self.problem.n_variables()
    }

    /// The inequality rows `C f <= b` in world axes for sole rotations `world_R_sole`
    /// (for checks: the solvers work in the sole frames).
    pub fn inequalities(&self, sole_rotations: &[Matrix3<f64>]) -> (DMatrix<f64>, DVector<f64>) {
        self.problem.world_inequalities(sole_rotations)
    }

    /// Whether the world wrenches `f` satisfy every contact inequality (`C f <= b`, exactly) for
    /// sole rotations `world_R_sole`.
    pub fn satisfies_inequalities(
        &self,
        f: &DVector<f64>,
        sole_rotations: &[Matrix3<f64>],
    ) -> bool {
        self.problem.satisfies_inequalities(f, sole_rotations)
    }

    /// Solves `min 0.5 f^T P f + c^T f` s.t. `A_eq f = b_eq`, `C f <= b` (world wrenches) into
    /// `wrenches` (k), the contacts' sole rotations `world_R_sole` in `sole_rotations`.
    /// `unconstrained` is the minimiser without `C f <= b` (None if it could not be computed):
    /// returned directly when feasible (see the module doc), and on Clarabel's failure
    /// returned with a `Fallback` status (zeros if None); otherwise the active set or Clarabel
    /// solves (the order of the module doc). `P` must be symmetric positive definite (k x k).
    /// The active-set path allocates nothing; Clarabel allocates when it builds its solver
    /// (first solve), its own work, and a failure's message.
    pub fn solve(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        sole_rotations: &[Matrix3<f64>],
        unconstrained: Option<&DVector<f64>>,
        wrenches: &mut DVector<f64>,
    ) -> QpStatus {
        if let Some(f) = unconstrained {
            if self.unconstrained_first && self.satisfies_inequalities(f, sole_rotations) {
                self.counters.unconstrained += 1;
                wrenches.copy_from(f);
                return QpStatus::Solved;
            }
        }
        let (a_eq, b_eq) = (equality.map(|(a, _)| a), equality.map(|(_, b)| b));
        self.problem.set(hessian, gradient, a_eq, sole_rotations);
        if self.solver == QpSolver::ActiveSet {
            if let Some(active) = self.solve_active_set(b_eq) {
                if self.cross_check {
                    self.compare_with_clarabel(b_eq, active);
                }
                self.problem.to_world(&self.solution_sole, wrenches);
                return QpStatus::Solved;
            }
        }
        self.counters.clarabel += 1;
        let problem = &self.problem;
        match self.clarabel.solve(problem, b_eq, &mut self.solution_sole) {
            Ok(()) => {
                self.problem.to_world(&self.solution_sole, wrenches);
                QpStatus::Solved
            }
            Err(reason) => {
                self.counters.fallbacks += 1;
                match unconstrained {
                    Some(f) => wrenches.copy_from(f),
                    None => wrenches.as_mut_slice().fill(0.0),
                }
                QpStatus::Fallback(reason)
            }
        }
    }

    /// The active set on the sole-frame problem (`b_eq` the equality targets), the solution
    /// into `solution_sole`; the number of active inequalities, or `None` (counted) when it
    /// fails.
    fn solve_active_set(&mut self, b_eq: Option<&DVector<f64>>) -> Option<usize> {
        let problem = &self.problem;
        let equality = b_eq.map(|b| (&problem.equality, b));
        let result = self.active_set.solve(
            &problem.hessian,
            &problem.gradient,
            equality,
            &mut self.solution_sole,
        );
        match result {
            Ok(report) => {
                self.counters.active_set += 1;
                Some(report.active_inequalities)
            }
            Err(error) => {
                self.counters.active_set_failures += 1;
                self.last_active_set_failure = Some(error);
                None
            }
        }
    }

    /// The cross-check of the active set's solution (in `solution_sole`, with `active`
    /// inequalities active) against Clarabel into [`Self::agreement`].
    fn compare_with_clarabel(&mut self, b_eq: Option<&DVector<f64>>, active: usize) {
        let compared = Compared {
            problem: &self.problem,
            b_eq,
            active_set: &self.active_set,
            clarabel: &mut self.clarabel,
            checked: &self.solution_sole,
            active,
        };
        self.cross_check_buffers
            .compare(compared, &mut self.agreement);
    }
}
