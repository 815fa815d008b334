//! The closed loop as an autonomous system: the controller is static state feedback (its
//! integral terms are functions of the state), so with the references frozen at one instant
//! the loop is `xdot = f(x) = F(x, u(x))` in continuous time, or the map
//! `x_{k+1} = Phi(x_k)` over one control period with `u(x_k)` held (zero-order hold).
//!
//! Both live on the state manifold; vectors are on its tangent space
//! `dx = [dq (nv); dtheta (n_e); dnu (nv); dthetadot (n_e)]` (see `sea_dyn::StateLayout`),
//! with `x (+) dx` = [`sea_plant::retract`] and `y (-) x` = [`difference`].

use crate::error::{Error, Result};
use crate::scenario::{Sampling, Scenario, Setup};
use nalgebra::DVector;
use sea_ctrl::controller::{ControlOutput, MomentumController};
use sea_ctrl::references::ComSample;
use sea_plant::{Method, Plant, PlantData, StateLayout};

/// When the controller is evaluated: the sampling setting ([`Sampling`]) with, in zero-order
/// hold, its period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControlTiming {
    /// Evaluated wherever the dynamics are (the paper's setting: inside ode15s).
    Continuous,
    /// Evaluated every `period` seconds and held in between.
    ZeroOrderHold {
        /// Control period [s].
        period: f64,
    },
}

impl ControlTiming {
    /// The timing of `sampling` at the control rate `rate_hz` (used in zero-order hold).
    pub fn of(sampling: Sampling, rate_hz: f64) -> ControlTiming {
        match sampling {
            Sampling::Continuous => ControlTiming::Continuous,
            Sampling::ZeroOrderHold => ControlTiming::ZeroOrderHold {
                period: 1.0 / rate_hz,
            },
        }
    }

    /// The scenario's timing: `controller.sampling`, the period from `controller.rate_hz`.
    pub fn of_scenario(scenario: &Scenario) -> ControlTiming {
        Self::of(scenario.controller.sampling, scenario.controller.rate_hz)
    }

    /// The sampling setting.
    pub fn sampling(&self) -> Sampling {
        match self {
            ControlTiming::Continuous => Sampling::Continuous,
            ControlTiming::ZeroOrderHold { .. } => Sampling::ZeroOrderHold,
        }
    }

    /// The control period [s] (`None` in continuous time).
    pub fn period(&self) -> Option<f64> {
        match *self {
            ControlTiming::Continuous => None,
            ControlTiming::ZeroOrderHold { period } => Some(period),
        }
    }

    /// A short label: "continuous" or "zero_order_hold at R Hz".
    pub fn label(&self) -> String {
        match self.period() {
            None => self.sampling().name().into(),
            Some(period) => format!("{} at {:.6} Hz", self.sampling().name(), 1.0 / period),
        }
    }
}

/// `y (-) x`: the tangent vector `dx` with `x (+) dx = y` (base rotation by the logarithm of
/// `R_y R_x^T`, world axes, matching `sea_dyn::configuration::integrate`; the rest linear).
pub fn difference(layout: &StateLayout, x: &[f64], y: &[f64], out: &mut DVector<f64>) {
    let (nq, nv) = (layout.nq, layout.nv);
    for k in 0..3 {
        out[k] = y[k] - x[k];
    }
    // q_y q_x^-1 (unit quaternions: the inverse is the conjugate).
    let conjugate = [x[3], -x[4], -x[5], -x[6]];
    let mut relative =
        sea_dyn::configuration::quaternion_multiply([y[3], y[4], y[5], y[6]], conjugate);
    if relative[0] < 0.0 {
        relative.iter_mut().for_each(|c| *c = -*c);
    }
    let sin_half = (relative[1].powi(2) + relative[2].powi(2) + relative[3].powi(2)).sqrt();
    let angle = 2.0 * sin_half.atan2(relative[0]);
    // angle / sin(angle/2), by its series near zero.
    let factor = if sin_half < 1e-8 {
        2.0
    } else {
        angle / sin_half
    };
    for k in 0..3 {
        out[3 + k] = factor * relative[1 + k];
    }
    for k in 7..nq {
        out[k - 1] = y[k] - x[k];
    }
    for k in nq..x.len() {
        out[k - (nq - nv)] = y[k] - x[k];
    }
}

/// The closed loop with the references frozen: model, plant, controller and buffers.
pub struct ClosedLoopSystem {
    /// The built scenario (plant, controller, initial state, references).
    pub setup: Setup,
    /// The state layout.
    pub layout: StateLayout,
    /// The frozen CoM reference (position at the chosen time, zero velocity and acceleration).
    pub reference: ComSample,
    /// The frozen desired posture.
    pub s_desired: Vec<f64>,
    /// When the controller is evaluated.
    pub sampling: ControlTiming,
    /// Plant steps per control period (zero-order hold).
    pub steps_per_period: usize,
    /// Integration method of the plant.
    pub method: Method,
    pd: PlantData,
    /// The controller's output at the last state given to it.
    output: ControlOutput,
    x_step: Vec<f64>,
    x_next: Vec<f64>,
}

impl ClosedLoopSystem {
    /// The closed loop of `setup` with the references frozen at time `t`; in zero-order hold
    /// the period is split into the smallest whole number of equal steps not longer than
    /// `plant_dt`.
    pub fn new(
        setup: Setup,
        t: f64,
        sampling: ControlTiming,
        plant_dt: f64,
        method: Method,
    ) -> Result<Self> {
        if !t.is_finite() {
            return Err(Error::config("t", format!("must be finite, got {t}")));
        }
        let layout = setup.plant.layout();
        let mut reference = setup.com_reference.sample(t);
        reference.velocity.fill(0.0);
        reference.acceleration.fill(0.0);
        let mut s_desired = vec![0.0; setup.model.n_joints()];
        setup.posture.at(t, &mut s_desired);
        let steps_per_period = match sampling {
            ControlTiming::Continuous => 1,
            ControlTiming::ZeroOrderHold { period } => {
                if !(period.is_finite() && period > 0.0) {
                    return Err(Error::config(
                        "controller.rate_hz",
                        format!("control period must be positive, got {period}"),
                    ));
                }
                crate::closed_loop::equal_steps(period, plant_dt)
            }
        };
        let pd = PlantData::new(&setup.plant);
        let nx = layout.nx();
        Ok(Self {
            layout,
            reference,
            s_desired,
            sampling,
            steps_per_period,
            method,
            pd,
            output: setup.controller.new_output(),
            x_step: vec![0.0; nx],
            x_next: vec![0.0; nx],
            setup,
        })
    }

    /// The plant.
    pub fn plant(&self) -> &Plant {
        &self.setup.plant
    }

    /// The controller.
    pub fn controller(&self) -> &MomentumController {
        &self.setup.controller
    }

    /// The control period [s] (`None` in continuous time).
    pub fn period(&self) -> Option<f64> {
        self.sampling.period()
    }

    /// Computes and stores the controller's input at `x`.
    fn control(&mut self, x: &[f64]) -> Result<()> {
        self.setup.controller.compute_into(
            x,
            &self.layout,
            &self.reference,
            &self.s_desired,
            &mut self.output,
        )?;
        Ok(())
    }

    /// `out = f(x)`, the closed-loop vector field (tangent derivative) in continuous time.
    pub fn vector_field(&mut self, x: &[f64], out: &mut DVector<f64>) -> Result<()> {
        self.control(x)?;
        sea_plant::evaluate(
            &self.setup.plant,
            &mut self.pd.workspace,
            x,
            &self.output.input,
            &mut self.pd.outputs,
        )?;
        out.copy_from(&self.pd.outputs.xdot);
        Ok(())
    }

    /// `x_out = Phi(x)`: the plant over one control period with the input `u(x)` held.
    pub fn period_map(&mut self, x: &[f64], x_out: &mut [f64]) -> Result<()> {
        let period = self.period().ok_or_else(|| {
            Error::config(
                "controller.sampling",
                "continuous sampling has no period map",
            )
        })?;
        self.control(x)?;
        let dt = period / self.steps_per_period as f64;
        self.x_step.copy_from_slice(x);
        for _ in 0..self.steps_per_period {
            sea_plant::step(
                &self.setup.plant,
                &mut self.pd,
                &self.x_step,
                &self.output.input,
                dt,
                self.method,
                &mut self.x_next,
            )?;
            std::mem::swap(&mut self.x_step, &mut self.x_next);
        }
        x_out.copy_from_slice(&self.x_step);
        Ok(())
    }

    /// The linearised object's value at `x`: `f(x)` in continuous time, `Phi(x) (-) x` over one
    /// period in zero-order hold (the displacement of one period).
    pub fn displacement(&mut self, x: &[f64], out: &mut DVector<f64>) -> Result<()> {
        match self.sampling {
            ControlTiming::Continuous => self.vector_field(x, out),
            ControlTiming::ZeroOrderHold { .. } => {
                let mut mapped = vec![0.0; x.len()];
                self.period_map(x, &mut mapped)?;
                difference(&self.layout, x, &mapped, out);
                Ok(())
            }
        }
    }
}
