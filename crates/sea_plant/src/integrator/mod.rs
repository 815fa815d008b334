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
//! evaluation `eval(pd, time offset, x_stage)`.

use crate::dynamics::{evaluate, PlantData};
use crate::error::{Error, Result};
use crate::manifold::retract;
use crate::plant::Plant;
use nalgebra::DVector;
use sea_dyn::dense::copy_contiguous;
pub(crate) use w_matrix::MotorElimination;
use w_matrix::{prepare_implicit, solve_implicit};

mod w_matrix;

/// Integration method; with the `serde` feature, named "ros2", "implicit_euler" or "rk4".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize),
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

impl Method {
    /// Parses "ros2", "implicit_euler" or "rk4".
    pub fn parse(name: &str) -> Result<Method> {
        match name {
            "ros2" => Ok(Method::Ros2),
            "implicit_euler" => Ok(Method::LinearlyImplicitEuler),
            "rk4" => Ok(Method::Rk4),
            other => Err(Error::invalid(
                "method",
                "'ros2', 'implicit_euler' or 'rk4'",
                format!("'{other}'"),
            )),
        }
    }
}

/// `gamma` of ROS2.
const GAMMA: f64 = 1.0 + std::f64::consts::FRAC_1_SQRT_2;

/// One step of size `dt` from `x` with input `u` held; writes `x_out`. On return `pd` holds the
/// evaluation at `x` (contact wrenches, torques, drift of the step start).
pub fn step(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    u: &[f64],
    dt: f64,
    method: Method,
    x_out: &mut [f64],
) -> Result<()> {
    let mut held =
        |pd: &mut PlantData, _offset: f64, x_stage: &[f64]| evaluate(plant, pd, x_stage, u);
    step_with(plant, pd, x, dt, method, &mut held, x_out)
}

/// One step of size `dt` from `x` at time `t` whose input is the feedback law
/// `law(t_stage, x_stage, u, pd)`, evaluated at every stage, the way a controller inside an ODE
/// solver's right-hand side is (the paper's setting); writes `x_out`. `u` (n) is the law's
/// output buffer. Stage times: `t` (linearly implicit Euler), `t, t + dt` (ROS2),
/// `t, t + dt/2, t + dt/2, t + dt` (RK4); the first stage is always `(t, x)`. `W` keeps only
/// the plant's stiff terms (the law is treated explicitly), which a W-method allows without
/// losing its order. On success `pd` holds the evaluation at `x`. The law also gets the
/// plant's workspace, to hand over model terms it computed at the stage's state
/// ([`PlantData::adopt_model_terms`]); it must not change anything else there.
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
    law: &mut impl FnMut(f64, &[f64], &mut [f64], &mut PlantData) -> std::result::Result<(), E>,
    u: &mut [f64],
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let mut feedback = |pd: &mut PlantData, offset: f64, x_stage: &[f64]| {
        law(t + offset, x_stage, u, pd)?;
        evaluate(plant, pd, x_stage, u).map_err(E::from)
    };
    step_with(plant, pd, x, dt, method, &mut feedback, x_out)
}

/// One step whose dynamics at each stage come from `eval(pd, offset, x_stage)`: the stage's
/// time offset from the step start and its state; `eval` leaves the derivative in `pd`.
fn step_with<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    method: Method,
    eval: &mut impl FnMut(&mut PlantData, f64, &[f64]) -> std::result::Result<(), E>,
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
    eval: &mut impl FnMut(&mut PlantData, f64, &[f64]) -> std::result::Result<(), E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let [k1, mut k2, mut rhs, combo] = implicit_first_stage(plant, pd, x, GAMMA * dt, eval)?;
    // Keep the step-start outputs (the W solve leaves them alone): the second evaluation
    // would overwrite them.
    pd.save_outputs();
    let mut x_stage = std::mem::take(&mut pd.x_stage);
    retract(plant, x, &k1, dt, &mut x_stage);
    // The second stage sits at t + dt: the time row of W is the identity, so k1_t = 1.
    let second = eval(pd, dt, &x_stage);
    if second.is_ok() {
        linear_combination(&mut rhs, [(1.0, &pd.xdot), (-2.0, &k1)]);
        solve_implicit(plant, pd, &rhs, &mut k2);
        linear_combination(&mut rhs, [(1.5, &k1), (0.5, &k2)]);
        retract(plant, x, &rhs, dt, x_out);
    }
    pd.stage = [k1, k2, rhs, combo];
    pd.x_stage = x_stage;
    pd.restore_outputs();
    second
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
        *o = a * xi + b * yi;
    }
}

fn implicit_euler<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    eval: &mut impl FnMut(&mut PlantData, f64, &[f64]) -> std::result::Result<(), E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let [k1, k2, rhs, combo] = implicit_first_stage(plant, pd, x, dt, eval)?;
    retract(plant, x, &k1, dt, x_out);
    pd.stage = [k1, k2, rhs, combo];
    Ok(())
}

/// The first stage of the linearly implicit methods: the dynamics at the step start, `W`
/// prepared for `g` (`gamma dt`) and `W k1 = f(x)` solved. Returns the stage buffers
/// `[k1, k2, rhs, combo]` taken from `pd`; the caller gives them back.
fn implicit_first_stage<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    g: f64,
    eval: &mut impl FnMut(&mut PlantData, f64, &[f64]) -> std::result::Result<(), E>,
) -> std::result::Result<[DVector<f64>; 4], E> {
    eval(pd, 0.0, x)?;
    prepare_implicit(plant, pd, g)?;
    let [mut k1, k2, mut rhs, combo] = std::mem::take(&mut pd.stage);
    copy_contiguous(&mut rhs, &pd.xdot);
    solve_implicit(plant, pd, &rhs, &mut k1);
    Ok([k1, k2, rhs, combo])
}

/// Runge-Kutta-Munthe-Kaas correction of a stage's base angular velocity: the stage sits at
/// `R = exp([u]x) R_n` with `u = scale * previous_omega`, and the rotation vector evolves as
/// `udot = dexp_u^-1(omega) = omega - u x omega / 2 + u x (u x omega) / 12 + O(|u|^4)`, the
/// terms a fourth-order method needs (Munthe-Kaas, BIT 38, 1998).
fn dexp_inv_correction(stage: &mut DVector<f64>, previous: &DVector<f64>, scale: f64) {
    let omega = nalgebra::Vector3::new(stage[3], stage[4], stage[5]);
    let u = nalgebra::Vector3::new(previous[3], previous[4], previous[5]) * scale;
    let u_cross_omega = u.cross(&omega);
    let corrected = omega - u_cross_omega * 0.5 + u.cross(&u_cross_omega) / 12.0;
    stage[3] = corrected.x;
    stage[4] = corrected.y;
    stage[5] = corrected.z;
}

/// Classical RK4 as a Runge-Kutta-Munthe-Kaas method on the base rotation.
fn rk4<E: From<Error>>(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    dt: f64,
    eval: &mut impl FnMut(&mut PlantData, f64, &[f64]) -> std::result::Result<(), E>,
    x_out: &mut [f64],
) -> std::result::Result<(), E> {
    let [mut k1, mut k2, mut k3, mut sum] = std::mem::take(&mut pd.stage);
    let mut x_stage = std::mem::take(&mut pd.x_stage);
    let result = (|| {
        eval(pd, 0.0, x)?;
        pd.save_outputs();
        copy_contiguous(&mut k1, &pd.xdot);
        retract(plant, x, &k1, 0.5 * dt, &mut x_stage);
        eval(pd, 0.5 * dt, &x_stage)?;
        copy_contiguous(&mut k2, &pd.xdot);
        dexp_inv_correction(&mut k2, &k1, 0.5 * dt);
        retract(plant, x, &k2, 0.5 * dt, &mut x_stage);
        eval(pd, 0.5 * dt, &x_stage)?;
        copy_contiguous(&mut k3, &pd.xdot);
        dexp_inv_correction(&mut k3, &k2, 0.5 * dt);
        retract(plant, x, &k3, dt, &mut x_stage);
        eval(pd, dt, &x_stage)?;
        // sum = (k1 + 2 k2 + 2 k3 + k4) / 6
        copy_contiguous(&mut sum, &pd.xdot);
        dexp_inv_correction(&mut sum, &k3, dt);
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
        retract(plant, x, &sum, dt, x_out);
        pd.restore_outputs();
        Ok(())
    })();
    pd.stage = [k1, k2, k3, sum];
    pd.x_stage = x_stage;
    result
}
