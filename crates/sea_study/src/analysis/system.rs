//! The closed loop as an autonomous system: the controller is static state feedback (its
//! integral terms are functions of the state), so with the references frozen at one instant
//! the loop is `xdot = f(x) = F(x, u(x))` in continuous time, or the map
//! `x_{k+1} = Phi(x_k)` over one control period with `u(x_k)` held (zero-order hold). In
//! multi-rate sampling `Phi` is the map over one whole-body period: the controller's torques
//! held, the joint torque loops ticking at the inner rate on the measured state; its
//! continuous-time counterpart `f` runs the joint loops continuously (the equilibria agree).
//!
//! Both live on the state manifold; vectors are on its tangent space
//! `dx = [dq (nv); dtheta (n_e); dnu (nv); dthetadot (n_e)]` (see `sea_dyn::StateLayout`),
//! with `x (+) dx` = [`sea_plant::retract`] and `y (-) x` = [`difference`].
//!
//! A measurement delay of `d` inner periods (`sensing.delay_inner_periods`, sampled loops
//! only) makes the map's state the history `z = [x(t); x(t - h); ...; x(t - d h)]`, `h` the
//! inner period (the control period in zero-order hold): the controller's tick `j` of the
//! period reads `x(t + (j - d) h)`, from `z` while `j < d`, and `Phi(z)` is the history at
//! `t + T`, which the period's own inner states fill because `d h <= T`. Each of the `d + 1`
//! slots is a state (`nx`) and its tangent (`nd`); `d = 0` is the map above.

use crate::error::{Error, Result};
use nalgebra::DVector;
use sea_ctrl::controller::{ControlOutput, MomentumController};
use sea_ctrl::joint_loop::JointTorqueLoop;
use sea_ctrl::references::ComSample;
use sea_ctrl::stiffness_id::StiffnessIdentifier;
use sea_plant::{Method, Plant, PlantData, StateLayout};
use sea_scenario::IdentificationWrenches;
use sea_scenario::{ControllerConfig, Sampling, Scenario, Setup};

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
    /// The whole-body controller every `period` seconds, its torques held; the joint torque
    /// loops `inner_ticks` times per period.
    MultiRate {
        /// Whole-body period [s].
        period: f64,
        /// Joint loop ticks per period.
        inner_ticks: usize,
        /// The joint loops' bandwidth [rad/s] (`None`: the paper's `K_S^ / K_D^`).
        bandwidth: Option<f64>,
    },
}

impl ControlTiming {
    /// The timing of `sampling` with the rates and bandwidth of `controller`
    /// (`controller.rate_hz`, `inner_rate_hz`, the torque loop's bandwidth).
    pub fn of(sampling: Sampling, controller: &ControllerConfig) -> ControlTiming {
        let period = 1.0 / controller.rate_hz();
        match sampling {
            Sampling::Continuous => ControlTiming::Continuous,
            Sampling::ZeroOrderHold => ControlTiming::ZeroOrderHold { period },
            Sampling::MultiRate => ControlTiming::MultiRate {
                period,
                inner_ticks: sea_loop::inner_ticks(controller.rate_hz(), controller.inner_rate_hz),
                bandwidth: controller.torque_bandwidth(),
            },
        }
    }

    /// The scenario's timing: `controller.sampling`, the period from `controller.rate_hz`.
    pub fn of_scenario(scenario: &Scenario) -> ControlTiming {
        Self::of(scenario.controller.sampling, &scenario.controller)
    }

    /// The sampling setting.
    pub fn sampling(&self) -> Sampling {
        match self {
            ControlTiming::Continuous => Sampling::Continuous,
            ControlTiming::ZeroOrderHold { .. } => Sampling::ZeroOrderHold,
            ControlTiming::MultiRate { .. } => Sampling::MultiRate,
        }
    }

    /// The control period [s] (`None` in continuous time).
    pub fn period(&self) -> Option<f64> {
        match *self {
            ControlTiming::Continuous => None,
            ControlTiming::ZeroOrderHold { period } | ControlTiming::MultiRate { period, .. } => {
                Some(period)
            }
        }
    }

    /// Joint loop ticks per period (1 unless multi-rate).
    pub fn inner_ticks(&self) -> usize {
        match *self {
            ControlTiming::MultiRate { inner_ticks, .. } => inner_ticks.max(1),
            _ => 1,
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
    /// Plant steps per control period (zero-order hold, multi-rate).
    pub steps_per_period: usize,
    /// The joint torque loops (multi-rate).
    joint_loop: Option<JointTorqueLoop>,
    /// Measurement delay in inner periods (sampled loops; 0 in continuous time).
    delay: usize,
    /// The true states at the period's inner ticks and at its end ((inner ticks + 1) x nx).
    inner_states: Vec<f64>,
    /// The stiffness identification feeding the joint loops, linearised converged
    /// ([`ClosedLoopSystem::converge_identification`]).
    identifier: Option<(StiffnessIdentifier, IdentificationWrenches)>,
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
        let steps_per_period = match sampling.period() {
            None => 1,
            Some(period) => {
                if !(period.is_finite() && period > 0.0) {
                    return Err(Error::config(
                        "controller.rate_hz",
                        format!("control period must be positive, got {period}"),
                    ));
                }
                let inner = sampling.inner_ticks();
                inner * sea_loop::equal_steps(period / inner as f64, plant_dt)
            }
        };
        let joint_loop = match sampling {
            ControlTiming::MultiRate { bandwidth, .. } => {
                Some(JointTorqueLoop::new(&setup.controller, bandwidth))
            }
            _ => None,
        };
        let pd = PlantData::new(&setup.plant);
        let nx = layout.nx();
        Ok(Self {
            layout,
            reference,
            s_desired,
            sampling,
            steps_per_period,
            joint_loop,
            delay: 0,
            inner_states: vec![0.0; (sampling.inner_ticks() + 1) * nx],
            identifier: None,
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

    /// The joint torque loops (multi-rate), e.g. to give each joint its own estimate.
    pub fn joint_loop_mut(&mut self) -> Option<&mut JointTorqueLoop> {
        self.joint_loop.as_mut()
    }

    /// Sets the measurement delay to `delay` inner periods (`sensing.delay_inner_periods`):
    /// the period map's state becomes the history of `delay + 1` states (module doc). Refused
    /// in continuous time (a delay there has infinitely many states) and beyond one period.
    pub fn set_delay(&mut self, delay: usize) -> Result<()> {
        const KEY: &str = "sensing.delay_inner_periods";
        if delay > 0 && self.sampling == ControlTiming::Continuous {
            return Err(Error::invalid(
                KEY,
                "must be 0 to linearise in continuous time (a delayed loop has no finite \
                 state there; linearise the sampled loop)",
                delay,
            ));
        }
        let inner_ticks = self.sampling.inner_ticks();
        if delay > inner_ticks {
            return Err(Error::invalid(
                KEY,
                format!("must be at most the {inner_ticks} inner periods of one control period"),
                delay,
            ));
        }
        self.delay = delay;
        Ok(())
    }

    /// Lets up to `steps` consecutive plant steps share the implicit step's `W`
    /// (`plant.w_refresh_steps`); each period map prepares its own at its start, so the map
    /// is a function of its argument alone.
    pub fn set_w_refresh_steps(&mut self, steps: usize) {
        self.pd.integrator.set_w_refresh_steps(steps);
    }

    /// States in the linearised object's state: `delay + 1` for a period map, 1 in continuous
    /// time.
    pub fn slots(&self) -> usize {
        match self.sampling {
            ControlTiming::Continuous => 1,
            _ => self.delay + 1,
        }
    }

    /// Replaces the joint torque loops (`None`: the controller's input goes to the plant as
    /// it is). A multi-rate scenario's loops apply whatever the timing: continuous time runs
    /// them continuously, zero-order hold ticks them once per period.
    pub fn set_joint_loop(&mut self, joint_loop: Option<JointTorqueLoop>) {
        self.joint_loop = joint_loop;
    }

    /// Gives the joint loops a stiffness identification (multi-rate,
    /// `controller.stiffness_identification`).
    pub fn set_identifier(
        &mut self,
        identifier: Option<(StiffnessIdentifier, IdentificationWrenches)>,
    ) {
        self.identifier = identifier;
    }

    /// With a stiffness identification: sets the joint loops' stiffness estimates to the
    /// identification's fixed point at `x` held still
    /// ([`StiffnessIdentifier::converged_at`]) with the commanded or the plant's contact
    /// wrenches at `x`, and returns true; false without one.
    pub fn converge_identification(&mut self, x: &[f64]) -> Result<bool> {
        if self.identifier.is_none() || self.joint_loop.is_none() {
            return Ok(false);
        }
        let mut xdot = DVector::zeros(self.layout.nd());
        self.vector_field(x, &mut xdot)?;
        let (Some((identifier, source)), Some(joint_loop)) =
            (&mut self.identifier, &mut self.joint_loop)
        else {
            return Ok(false);
        };
        let wrenches = match source {
            IdentificationWrenches::Measured => &self.pd.outputs.contact_wrench,
            IdentificationWrenches::Commanded => &self.output.wrenches,
        };
        let estimates = joint_loop.estimates_mut();
        identifier.converged_at(&self.layout, x, wrenches, estimates);
        Ok(true)
    }

    /// Computes and stores the controller's input at `x` (multi-rate: holds its torques and
    /// ticks the joint loops at `x`).
    fn control(&mut self, x: &[f64]) -> Result<()> {
        self.setup.controller.compute_into(
            x,
            &self.layout,
            &self.reference,
            &self.s_desired,
            &mut self.output,
        )?;
        if let Some(joint_loop) = &mut self.joint_loop {
            joint_loop.hold(&self.output, &self.layout, x, &self.s_desired);
            joint_loop.tick(&self.layout, x);
        }
        Ok(())
    }

    /// `out = f(x)`, the closed-loop vector field (tangent derivative) in continuous time.
    pub fn vector_field(&mut self, x: &[f64], out: &mut DVector<f64>) -> Result<()> {
        self.control(x)?;
        sea_plant::evaluate(
            &self.setup.plant,
            &mut self.pd.workspace,
            x,
            match &self.joint_loop {
                Some(joint_loop) => joint_loop.input(),
                None => &self.output.input,
            },
            &mut self.pd.outputs,
        )?;
        out.copy_from(&self.pd.outputs.xdot);
        Ok(())
    }

    /// `z_out = Phi(z)`: the plant over one control period with the input `u` held
    /// (multi-rate: the torques held, the joint loops ticking on the measured state). `z` and
    /// `z_out` are histories of [`ClosedLoopSystem::slots`] states, newest first (module doc);
    /// without a delay, one state.
    pub fn period_map(&mut self, z: &[f64], z_out: &mut [f64]) -> Result<()> {
        let period = self.period().ok_or_else(|| {
            Error::config(
                "controller.sampling",
                "continuous sampling has no period map",
            )
        })?;
        let (nx, delay) = (self.layout.nx(), self.delay);
        let inner_ticks = self.sampling.inner_ticks();
        self.inner_states[..nx].copy_from_slice(&z[..nx]);
        // Tick 0 reads the history's oldest slot (`measurement` at tick 0).
        self.control(&z[delay * nx..(delay + 1) * nx])?;
        let dt = period / self.steps_per_period as f64;
        self.pd.integrator.refresh_w();
        self.x_step.copy_from_slice(&z[..nx]);
        let steps_per_inner = self.steps_per_period / inner_ticks;
        for k in 0..self.steps_per_period {
            if k > 0 && k % steps_per_inner == 0 {
                let tick = k / steps_per_inner;
                self.inner_states[tick * nx..(tick + 1) * nx].copy_from_slice(&self.x_step);
                if let Some(joint_loop) = &mut self.joint_loop {
                    let measured = measurement(z, &self.inner_states, tick, delay, nx);
                    joint_loop.tick(&self.layout, measured);
                }
            }
            sea_plant::step(
                &self.setup.plant,
                &mut self.pd,
                &self.x_step,
                match &self.joint_loop {
                    Some(joint_loop) => joint_loop.input(),
                    None => &self.output.input,
                },
                dt,
                self.method,
                &mut self.x_next,
            )?;
            std::mem::swap(&mut self.x_step, &mut self.x_next);
        }
        let end = inner_ticks * nx;
        self.inner_states[end..end + nx].copy_from_slice(&self.x_step);
        for (slot, out) in z_out.chunks_exact_mut(nx).enumerate() {
            let tick = inner_ticks - slot;
            out.copy_from_slice(&self.inner_states[tick * nx..(tick + 1) * nx]);
        }
        Ok(())
    }

    /// The linearised object's value at `x`: `f(x)` in continuous time, `Phi(z) (-) z` over one
    /// period when sampled (the displacement of one period; `z` a history of
    /// [`ClosedLoopSystem::slots`] states, [`difference_slots`]).
    pub fn displacement(&mut self, x: &[f64], out: &mut DVector<f64>) -> Result<()> {
        match self.sampling {
            ControlTiming::Continuous => self.vector_field(x, out),
            ControlTiming::ZeroOrderHold { .. } | ControlTiming::MultiRate { .. } => {
                let mut mapped = vec![0.0; x.len()];
                self.period_map(x, &mut mapped)?;
                difference_slots(&self.layout, x, &mapped, out);
                Ok(())
            }
        }
    }
}

/// The state the controller reads at inner tick `tick` of a period with a delay of `delay`
/// inner periods: `x(t + (tick - delay) h)`, from the history `z` (newest first) while
/// `tick < delay`, else from the period's own inner states.
fn measurement<'a>(
    z: &'a [f64],
    inner_states: &'a [f64],
    tick: usize,
    delay: usize,
    nx: usize,
) -> &'a [f64] {
    match tick.checked_sub(delay) {
        Some(past_tick) => &inner_states[past_tick * nx..(past_tick + 1) * nx],
        None => {
            let slot = delay - tick;
            &z[slot * nx..(slot + 1) * nx]
        }
    }
}

/// [`difference`] slot by slot for histories of states (`x.len() / nx` slots): `out` holds the
/// slots' tangent differences one after the other.
pub fn difference_slots(layout: &StateLayout, x: &[f64], y: &[f64], out: &mut DVector<f64>) {
    let (nx, nd) = (layout.nx(), layout.nd());
    let mut slot_out = DVector::zeros(nd);
    for (slot, (x_slot, y_slot)) in x.chunks_exact(nx).zip(y.chunks_exact(nx)).enumerate() {
        difference(layout, x_slot, y_slot, &mut slot_out);
        out.rows_mut(slot * nd, nd).copy_from(&slot_out);
    }
}
