//! Fixed-step integrators of the plant on its state manifold.
//!
//! The implicit method is ROS2 (Verwer, Spee, Blom, Hundsdorfer, SIAM J. Sci. Comput. 20,
//! 1999), a two-stage Rosenbrock-W method:
//! `W k1 = f(x_n)`, `W k2 = f(x_n (+) dt k1) - 2 k1`, `x_{n+1} = x_n (+) dt (1.5 k1 + 0.5 k2)`,
//! `W = I - gamma dt Jf`, `gamma = 1 + 1/sqrt(2)`.
//! Why this one: it is L-stable with the exact Jacobian and second order for ANY `W` (a
//! W-method), so `Jf` may keep only the stiff linear terms (springs, dampers, motor velocity
//! loop, Baumgarte stabilisation) with `M` and `J` frozen. That makes `W` cheap: the motor
//! unknowns are eliminated per joint, leaving one Cholesky of an nv x nv matrix and a k x k
//! Schur complement per step, and no Newton iterations (implicit Euler, SDIRK and Radau IIA
//! need them, with several evaluations per iteration). Two evaluations of the dynamics per
//! step. Stages are composed on the manifold with `(+)` (`plant::retract`): for a second-order
//! method the exponential map needs no commutator correction.
//!
//! Also: `LinearlyImplicitEuler` (one stage of the same `W`, first order, L-stable) and the
//! explicit classical `Rk4` (as Runge-Kutta-Munthe-Kaas on the rotation) for comparison.
//!
//! Inputs: [`step`] holds `u` over the step (a sampled controller, zero-order hold);
//! [`step_with_feedback`] evaluates a feedback law at every stage (a controller in continuous
//! time). Both run the same scheme code, which sees the dynamics only through a stage
//! evaluation `eval(workspace, outputs, time offset, x_stage)`.
//!
//! Reusing `W`: since any `W` keeps the order, [`IntegratorCache::set_w_refresh_steps`] lets
//! consecutive steps reuse the `W` (and its factors) prepared at an earlier step start, for at
//! most `N` steps: `M` and `J` change little over a few milliseconds while the stiff terms
//! `W` exists for (springs, dampers, the motor loop, Baumgarte) are constant. `W` is prepared
//! afresh whenever the step scale or a motor's saturation changes, and after
//! [`IntegratorCache::refresh_w`]. With `N = 1` (the default of a new cache) every step
//! prepares its own, and a step is a function of its arguments alone; with `N > 1` it also
//! depends on the state where `W` was last prepared (on the iCub with `N = 10` the paper's
//! tracking changes by 1e-12 relative, and the step's cost drops by the factorisations:
//! `benchmarks/README.md`).
//!
//! Buffers: the integrator owns its own ([`IntegratorCache`]: stage vectors, stage state, the
//! outputs of the later stages and the W-matrix); the evaluation owns its [`Workspace`]; the
//! step-start evaluation writes into the caller's [`PlantOutputs`]. [`PlantData`] bundles the
//! three for a caller that steps one plant.

use crate::error::{Error, Result};
use crate::evaluation::evaluate;
use crate::manifold::retract;
use crate::plant::Plant;
use crate::workspace::{PlantOutputs, Workspace};
use nalgebra::DVector;
use sea_dyn::dense::copy_contiguous;
use sea_dyn::linalg::mul_add;
use sea_dyn::TangentLayout;
use w_matrix::WMatrix;

mod w_matrix;

/// Integration method; with the `serde` feature, named "ros2", "implicit_euler" or "rk4".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum Method {
    /// ROS2 Rosenbrock-W, order 2, L-stable (the default).
    Ros2,
    /// Linearly implicit Euler (one stage of the same W), order 1.
    #[cfg_attr(feature = "serde", serde(rename = "implicit_euler"))]
    LinearlyImplicitEuler,
    /// Classical explicit Runge-Kutta, order 4.
    Rk4,
}

/// The integrator's own buffers, for every method.
#[derive(Clone, Debug)]
pub struct IntegratorCache {
    /// Stage vectors (nd each): ROS2 and linearly implicit Euler `[k1, k2, rhs, -]`, RK4
    /// `[k1, k2, k3, sum]`.
    stages: [DVector<f64>; 4],
    /// The state of a later stage (nx).
    x_stage: Vec<f64>,
    /// Outputs of the evaluations after the step start (not reported).
    stage_outputs: PlantOutputs,
    /// `W` of the linearly implicit methods.
    w: WMatrix,
    /// Steps that may share one `W` (at least 1).
    w_refresh_steps: usize,
    /// Steps taken with the current `W`; `None` when the next step must prepare it.
    w_age: Option<usize>,
    /// The motors' saturation when `W` was prepared (n_e).
    w_saturated: Vec<bool>,
    /// Which contact points and joint stops carried a force when `W` was prepared
    /// (points, then joints).
    w_active: Vec<bool>,
}

impl IntegratorCache {
    /// Buffers for `plant`.
    pub fn new(plant: &Plant) -> Self {
        let layout = plant.layout();
        Self {
            stages: std::array::from_fn(|_| DVector::zeros(layout.nd())),
            x_stage: vec![0.0; layout.nx()],
            stage_outputs: PlantOutputs::new(plant),
            w: WMatrix::new(plant),
            w_refresh_steps: 1,
            w_age: None,
            w_saturated: vec![false; layout.ne],
            w_active: vec![false; plant.n_contact_points() + plant.model.n_joints()],
        }
    }

    /// Lets up to `steps` consecutive steps share one `W` (module doc; 0 is taken as 1, every
    /// step its own).
    pub fn set_w_refresh_steps(&mut self, steps: usize) {
        self.w_refresh_steps = steps.max(1);
    }

    /// Makes the next step prepare `W` at its own start (e.g. at a period whose start state
    /// must not depend on earlier calls).
    pub fn refresh_w(&mut self) {
        self.w_age = None;
    }

    /// Whether a step of scale `g` whose start evaluated to `outputs` must prepare `W`: none
    /// yet, `N` steps on it already, another scale, saturation, or set of contact points and
    /// joint stops carrying a force.
    fn w_is_stale(&self, g: f64, outputs: &PlantOutputs) -> bool {
        match self.w_age {
            None => true,
            Some(age) => {
                let points = outputs.contact_point_active.len();
                age >= self.w_refresh_steps
                    || self.w.g() != g
                    || self.w_saturated != outputs.saturated
                    || self.w_active[..points] != outputs.contact_point_active[..]
                    || self.w_active[points..] != outputs.joint_stop_active[..]
            }
        }
    }

    /// `W` for a step of scale `g` from the evaluation in `ws` (with outputs `outputs`):
    /// prepared unless the current one may serve ([`IntegratorCache::w_is_stale`]).
    fn update_w(
        &mut self,
        plant: &Plant,
        ws: &Workspace,
        outputs: &PlantOutputs,
        g: f64,
    ) -> Result<()> {
        if self.w_is_stale(g, outputs) {
            self.w_age = None;
            self.w.prepare(plant, ws, &outputs.saturated, g)?;
            self.w_saturated.copy_from_slice(&outputs.saturated);
            let points = outputs.contact_point_active.len();
            self.w_active[..points].copy_from_slice(&outputs.contact_point_active);
            self.w_active[points..].copy_from_slice(&outputs.joint_stop_active);
            self.w_age = Some(0);
        }
        if let Some(age) = &mut self.w_age {
            *age += 1;
        }
        Ok(())
    }
}

/// What stepping one plant needs: the evaluation's workspace, the outputs of the last
/// evaluation at a step start (kept by the caller), and the integrator's buffers.
#[derive(Clone, Debug)]
pub struct PlantData {
    /// The evaluation's buffers; model and contact terms computed elsewhere are handed to it
    /// ([`Workspace::adopt_model_terms`], [`Workspace::adopt_contact_terms`]).
    pub workspace: Workspace,
    /// Outputs of the evaluation at the last step's start (or of an [`evaluate`] into them).
    pub outputs: PlantOutputs,
    /// The integrator's buffers.
    pub integrator: IntegratorCache,
}

impl PlantData {
    /// Buffers for `plant`.
    pub fn new(plant: &Plant) -> Self {
        Self {
            workspace: Workspace::new(plant),
            outputs: PlantOutputs::new(plant),
            integrator: IntegratorCache::new(plant),
        }
    }
}

/// The dynamics a scheme sees: `eval(workspace, outputs, offset, x_stage)` evaluates the stage
/// at time offset `offset` from the step start and state `x_stage`, writing the derivative
/// (and the other outputs) into `outputs`.
trait StageEvaluation<E>:
    FnMut(&mut Workspace, &mut PlantOutputs, f64, &[f64]) -> std::result::Result<(), E>
{
}

impl<E, F> StageEvaluation<E> for F where
    F: FnMut(&mut Workspace, &mut PlantOutputs, f64, &[f64]) -> std::result::Result<(), E>
{
}

/// `gamma` of ROS2.
const GAMMA: f64 = 1.0 + std::f64::consts::FRAC_1_SQRT_2;

/// One step of size `dt` from `x` with input `u` held; writes `x_out`. On return
/// `pd.outputs` holds the evaluation at `x` (derivative, contact wrenches, torques, drift of
/// the step start).
pub fn step(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    u: &[f64],
    dt: f64,
    method: Method,
    x_out: &mut [f64],
) -> Result<()> {
    let mut held = |ws: &mut Workspace, out: &mut PlantOutputs, _offset: f64, x_stage: &[f64]| {
        evaluate(plant, ws, x_stage, u, out)
    };
    step_with(plant, pd, x, dt, method, &mut held, x_out)
}

/// One step of size `dt` from `x` at time `t` whose input is the feedback law
/// `law(t_stage, x_stage, u, workspace)`, evaluated at every stage, the way a controller
/// inside an ODE solver's right-hand side is (the paper's setting); writes `x_out`. `u` (n) is
/// the law's output buffer. Stage times: `t` (linearly implicit Euler), `t, t + dt` (ROS2),
/// `t, t + dt/2, t + dt/2, t + dt` (RK4); the first stage is always `(t, x)`. `W` keeps only
/// the plant's stiff terms (the law is treated explicitly), which a W-method allows without
/// losing its order. On success `pd.outputs` holds the evaluation at `x`. The law also gets
/// the evaluation's workspace, to hand over model terms it computed at the stage's state
/// ([`Workspace::adopt_model_terms`]); it must not change anything else there.
///
/// The law's error type `E` is the caller's (any type a plant error converts into), so a
/// controller failure reaches the caller as itself.
#[allow(clippy::too_many_arguments)] // the step's inputs, as in `step`, plus the law's buffer
pub fn step_with_feedback<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    t: f64,
    dt: f64,
    method: Method,
    law: &mut impl FnMut(f64, &[f64], &mut [f64], &mut Workspace) -> std::result::Result<(), E>,
    u: &mut [f64],
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let mut feedback =
        |ws: &mut Workspace, out: &mut PlantOutputs, offset: f64, x_stage: &[f64]| {
            law(t + offset, x_stage, u, ws)?;
            evaluate(plant, ws, x_stage, u, out).map_err(E::from)
        };
    step_with(plant, pd, x, dt, method, &mut feedback, x_out)
}

/// One step whose dynamics at each stage come from `eval` ([`StageEvaluation`]).
fn step_with<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    method: Method,
    eval: &mut impl StageEvaluation<E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    match method {
        Method::Ros2 => ros2(plant, pd, x, dt, eval, x_out),
        Method::LinearlyImplicitEuler => implicit_euler(plant, pd, x, dt, eval, x_out),
        Method::Rk4 => rk4(plant, pd, x, dt, eval, x_out),
    }
}

fn ros2<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    eval: &mut impl StageEvaluation<E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    implicit_first_stage(plant, pd, x, GAMMA * dt, eval)?;
    // The step start's outputs stay in `pd.outputs`; the second stage evaluates into the
    // integrator's own.
    let (ws, cache) = (&mut pd.workspace, &mut pd.integrator);
    let [k1, k2, rhs, _] = &mut cache.stages;
    retract(plant, x, k1, dt, &mut cache.x_stage);
    // The second stage sits at t + dt: the time row of W is the identity, so k1_t = 1.
    eval(ws, &mut cache.stage_outputs, dt, &cache.x_stage)?;
    linear_combination(rhs, [(1.0, &cache.stage_outputs.xdot), (-2.0, k1)]);
    cache.w.solve(plant, rhs, k2);
    linear_combination(rhs, [(1.5, k1), (0.5, k2)]);
    retract(plant, x, rhs, dt, x_out);
    if plant.unilateral().is_some() {
        // 1.5 k1 + 0.5 k2 = (f(x) + g Jf k1) / 2 + (f(x2) + g Jf k2) / 2.
        let delivered = &mut pd.outputs.step_contact_wrench;
        let g = GAMMA * dt;
        cache.w.add_contact_response(plant, k1, g, delivered);
        delivered.axpy(0.5, &cache.stage_outputs.contact_wrench, 0.5);
        cache.w.add_contact_response(plant, k2, 0.5 * g, delivered);
    }
    Ok(())
}

/// `out = a x + b y` for `[(a, x), (b, y)]`, over the slices (nalgebra's vector `axpy` and
/// `scale_mut` step through strides entry by entry).
fn linear_combination(out: &mut DVector<f64>, [(a, x), (b, y)]: [(f64, &DVector<f64>); 2]) {
    for ((o, xi), yi) in out
        .as_mut_slice()
        .iter_mut()
        .zip(x.as_slice())
        .zip(y.as_slice())
    {
        *o = mul_add(a, *xi, b * yi);
    }
}

fn implicit_euler<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    eval: &mut impl StageEvaluation<E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    implicit_first_stage(plant, pd, x, dt, eval)?;
    retract(plant, x, &pd.integrator.stages[0], dt, x_out);
    // The step integrates f(x) + dt Jf k1.
    let k1 = &pd.integrator.stages[0];
    let delivered = &mut pd.outputs.step_contact_wrench;
    pd.integrator
        .w
        .add_contact_response(plant, k1, dt, delivered);
    Ok(())
}

/// The first stage of the linearly implicit methods: the dynamics at the step start (into
/// `pd.outputs`), `W` prepared for `g` (`gamma dt`) and `W k1 = f(x)` solved into the first
/// stage vector.
fn implicit_first_stage<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    g: f64,
    eval: &mut impl StageEvaluation<E>,
) -> std::result::Result<(), E> {
    let PlantData {
        workspace: ws,
        outputs,
        integrator: cache,
    } = pd;
    eval(ws, outputs, 0.0, x)?;
    cache.update_w(plant, ws, outputs, g)?;
    let [k1, _, rhs, _] = &mut cache.stages;
    copy_contiguous(rhs, &outputs.xdot);
    cache.w.solve(plant, rhs, k1);
    Ok(())
}

/// Runge-Kutta-Munthe-Kaas correction of a stage's base angular velocity: the stage sits at
/// `R = exp([u]x) R_n` with `u = scale * previous_omega`, and the rotation vector evolves as
/// `udot = dexp_u^-1(omega) = omega - u x omega / 2 + u x (u x omega) / 12 + O(|u|^4)`, the
/// terms a fourth-order method needs (Munthe-Kaas, BIT 38, 1998).
fn dexp_inv_correction(
    tangent: TangentLayout,
    stage: &mut DVector<f64>,
    previous: &DVector<f64>,
    scale: f64,
) {
    // The base's angular velocity: entries 3..6 of `dq` (`nu` in a derivative).
    let previous = tangent.dq(previous.as_slice());
    let stage = tangent.split_mut(stage.as_mut_slice()).dq;
    let omega = nalgebra::Vector3::new(stage[3], stage[4], stage[5]);
    let u = nalgebra::Vector3::new(previous[3], previous[4], previous[5]) * scale;
    let u_cross_omega = u.cross(&omega);
    let corrected = omega - u_cross_omega * 0.5 + u.cross(&u_cross_omega) / 12.0;
    stage[3] = corrected.x;
    stage[4] = corrected.y;
    stage[5] = corrected.z;
}

/// Under unilateral contacts, adds `weight` times a later stage's contact wrenches to the
/// step's delivered ones (RK4's weights 1, 2, 2, 1, divided by 6 at the end).
fn add_stage_wrench(plant: &Plant, outputs: &mut PlantOutputs, stage: &PlantOutputs, weight: f64) {
    if plant.unilateral().is_some() {
        outputs
            .step_contact_wrench
            .axpy(weight, &stage.contact_wrench, 1.0);
    }
}

/// Classical RK4 as a Runge-Kutta-Munthe-Kaas method on the base rotation.
fn rk4<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    eval: &mut impl StageEvaluation<E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let tangent = plant.layout().tangent();
    let PlantData {
        workspace: ws,
        outputs,
        integrator: cache,
    } = pd;
    let [k1, k2, k3, sum] = &mut cache.stages;
    let (stage, x_stage) = (&mut cache.stage_outputs, &mut cache.x_stage);
    eval(ws, outputs, 0.0, x)?;
    copy_contiguous(k1, &outputs.xdot);
    retract(plant, x, k1, 0.5 * dt, x_stage);
    eval(ws, stage, 0.5 * dt, x_stage)?;
    add_stage_wrench(plant, outputs, stage, 2.0);
    copy_contiguous(k2, &stage.xdot);
    dexp_inv_correction(tangent, k2, k1, 0.5 * dt);
    retract(plant, x, k2, 0.5 * dt, x_stage);
    eval(ws, stage, 0.5 * dt, x_stage)?;
    add_stage_wrench(plant, outputs, stage, 2.0);
    copy_contiguous(k3, &stage.xdot);
    dexp_inv_correction(tangent, k3, k2, 0.5 * dt);
    retract(plant, x, k3, dt, x_stage);
    eval(ws, stage, dt, x_stage)?;
    add_stage_wrench(plant, outputs, stage, 1.0);
    if plant.unilateral().is_some() {
        outputs.step_contact_wrench.scale_mut(1.0 / 6.0);
    }
    // sum = (k1 + 2 k2 + 2 k3 + k4) / 6
    copy_contiguous(sum, &stage.xdot);
    dexp_inv_correction(tangent, sum, k3, dt);
    // Over the slices, in the order of the formula (see `linear_combination`).
    for (((total, a), b), c) in sum
        .as_mut_slice()
        .iter_mut()
        .zip(k1.as_slice())
        .zip(k2.as_slice())
        .zip(k3.as_slice())
    {
        *total = (*total + a + 2.0 * b + 2.0 * c) * (1.0 / 6.0);
    }
    retract(plant, x, sum, dt, x_out);
    Ok(())
}
