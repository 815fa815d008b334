//! Linearisation of the closed loop about its equilibrium with the references frozen.
//!
//! 1. Equilibrium: Newton's method on the tangent space for `f(x) = 0`, starting from the
//!    scenario's initial state, with a backtracking line search on `|f|`; an unstable setting
//!    has the same equilibrium, so it can be analysed too. In zero-order hold the equilibrium is
//!    the same point: with `f(x) = 0` every stage of the held-input step vanishes, so
//!    `Phi(x) = x`; its residual `|Phi(x) (-) x|` is reported as well. With a stiffness
//!    identification (`controller.stiffness_identification`), its estimates are set to their
//!    fixed point at the initial state (the plant at rest) and again at the equilibrium found
//!    with them, which is then found once more: the map is that of
//!    the loop with the identification converged (its own slow dynamics, time constant
//!    `controller.identification_time_s`, are not states of the map).
//! 2. Jacobian on the tangent space by central differences (`A = df/dx` in continuous time,
//!    `A = dPhi/dx` over one control period in zero-order hold), at two relative steps; the
//!    change of the spectrum between them is reported, so a result that depends on the step is
//!    visible.
//! 3. Eigenvalues (balanced real Schur form), growth rates (`Re lambda`, or `log|mu| / T` for
//!    the map), and the eigenvector of the least stable mode with its dominant states.
//!
//! `[sensing]`: noise does not move the mean dynamics and is ignored. A measurement delay of
//! `d = sensing.delay_inner_periods` inner periods is in the map: its state is the history of
//! the last `d + 1` inner-tick states (`system` module doc), so the Jacobian is
//! `(d + 1) nd` square and the tangent coordinates of the older slots are named with the
//! suffix `@-i` (`i` inner periods earlier). The equilibrium is the undelayed loop's, every
//! slot at it. Continuous time has no finite-dimensional delayed state: a delay there is
//! refused, naming the key. So is an external wrench observer (`controller.external_wrench =
//! "observed"`), whose estimate is not a state of the map.

use super::eigen::{eigenvalues, eigenvector, spectrum_distance};
use super::system::{difference_slots, ClosedLoopSystem, ControlTiming};
use crate::error::{Error, Result};
use nalgebra::{Complex, DMatrix, DVector};
use sea_scenario::{ExternalWrench, Scenario, Setting};

/// Options of [`linearize_with`].
#[derive(Clone, Debug)]
pub struct LinearizeOptions {
    /// Time at which the references are frozen [s] (default 0).
    pub time: f64,
    /// Sampling (default: the scenario's `controller.sampling`, [`ControlTiming::of_scenario`]).
    pub sampling: Option<ControlTiming>,
    /// Relative finite-difference step of the reported Jacobian.
    pub step: f64,
    /// Second relative step, for the step-sensitivity check (`None`: no check).
    pub check_step: Option<f64>,
    /// Newton stops when `|f|_inf` is below this [units of the tangent derivative].
    pub tolerance: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
    /// How many dominant states to report.
    pub dominant_count: usize,
}

impl Default for LinearizeOptions {
    fn default() -> Self {
        Self {
            time: 0.0,
            sampling: None,
            step: 1e-6,
            check_step: Some(1e-7),
            tolerance: 1e-8,
            max_iterations: 30,
            dominant_count: 8,
        }
    }
}

/// The closed loop's equilibrium as found by Newton's method.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// The state (nx).
    pub state: Vec<f64>,
    /// Whether `|f|_inf` fell below the tolerance.
    pub converged: bool,
    /// `|f(x)|_inf` at the returned state.
    pub residual: f64,
    /// Newton iterations done.
    pub iterations: usize,
}

/// The linearised closed loop and its spectrum.
#[derive(Clone, Debug)]
pub struct Linearization {
    /// Sampling analysed.
    pub sampling: ControlTiming,
    /// Time at which the references were frozen [s].
    pub time: f64,
    /// The equilibrium (state, convergence, residual).
    pub equilibrium: Equilibrium,
    /// `|Phi(x) (-) x|_inf` at the equilibrium (zero-order hold only).
    pub map_residual: Option<f64>,
    /// The Jacobian on the tangent space: of `f` (continuous, nd x nd) or of `Phi` (sampled,
    /// `(d + 1) nd` square with a measurement delay of `d` inner periods).
    pub matrix: DMatrix<f64>,
    /// Its eigenvalues, least stable first (1/s in continuous time; multipliers of one period
    /// in zero-order hold).
    pub eigenvalues: Vec<Complex<f64>>,
    /// Growth rate of each eigenvalue [1/s]: `Re lambda`, or `log|mu| / T`.
    pub growth_rates: Vec<f64>,
    /// The largest growth rate [1/s].
    pub growth_rate: f64,
    /// Whether every growth rate is negative.
    pub stable: bool,
    /// The least stable eigenvalue as a continuous-time rate [1/s] (`log(mu) / T` sampled).
    pub least_stable_rate: Complex<f64>,
    /// Names of the tangent coordinates (as the matrix's rows; [`delayed_state_names`]).
    pub state_names: Vec<String>,
    /// The eigenvector of the least stable mode (as the matrix's rows, largest entry real
    /// positive).
    pub least_stable_mode: DVector<Complex<f64>>,
    /// Dominant states of that mode with their weights (largest 1), see [`dominant_states`].
    pub dominant_states: Vec<(String, f64)>,
    /// Relative finite-difference step of `matrix`.
    pub step: f64,
    /// Relative check step and the largest eigenvalue change between the two steps
    /// (`None` when not checked).
    pub step_check: Option<StepCheck>,
}

/// How much the spectrum changes with the finite-difference step.
#[derive(Clone, Copy, Debug)]
pub struct StepCheck {
    /// The second relative step.
    pub step: f64,
    /// Largest distance from an eigenvalue to the nearest one of the other step's spectrum,
    /// relative to `max(|lambda|, 1)`. Defective eigenvalues (the critically damped Baumgarte
    /// contact poles, `Kd = 2 sqrt(Kp)`) move by about the square root of the perturbation, so
    /// this is much larger than the change of a simple eigenvalue.
    pub eigenvalue_change: f64,
    /// Change of the least stable eigenvalue, relative to `max(|lambda|, 1)`.
    pub least_stable_change: f64,
    /// Change of the largest growth rate [1/s].
    pub growth_rate_change: f64,
}

/// Names of the tangent coordinates: `q:base_x`, `q:base_rx`, `s:JOINT`, `theta:JOINT`,
/// `nu:base_vx`, `nu:base_wx`, `sdot:JOINT`, `thetadot:JOINT`.
pub fn state_names(joint_names: &[String], elastic_names: &[String]) -> Vec<String> {
    let base = |prefix: &str, parts: [&str; 6]| -> Vec<String> {
        parts.iter().map(|p| format!("{prefix}:base_{p}")).collect()
    };
    fn named(prefix: &str, names: &[String]) -> Vec<String> {
        names.iter().map(|n| format!("{prefix}:{n}")).collect()
    }
    let mut out = base("q", ["x", "y", "z", "rx", "ry", "rz"]);
    out.extend(named("s", joint_names));
    out.extend(named("theta", elastic_names));
    out.extend(base("nu", ["vx", "vy", "vz", "wx", "wy", "wz"]));
    out.extend(named("sdot", joint_names));
    out.extend(named("thetadot", elastic_names));
    out
}

/// The tangent coordinates' names of a history of `slots` states: [`state_names`], then the
/// same names suffixed `@-i` for the state `i` inner periods earlier.
pub fn delayed_state_names(names: &[String], slots: usize) -> Vec<String> {
    let mut out = names.to_vec();
    for slot in 1..slots {
        out.extend(names.iter().map(|n| format!("{n}@-{slot}")));
    }
    out
}

/// Finite-difference scale of each tangent coordinate of a history `z` of states:
/// `max(1, |value|)` of the matching state entry (motor angles are large), 1 for the base
/// rotation.
fn coordinate_scales(system: &ClosedLoopSystem, z: &[f64]) -> Vec<f64> {
    let layout = system.layout;
    let nd = layout.nd();
    z.chunks_exact(layout.nx())
        .flat_map(|x| {
            (0..nd).map(move |k| match k {
                3..=5 => 1.0,
                0..=2 => x[k].abs().max(1.0),
                _ => x[k + 1].abs().max(1.0),
            })
        })
        .collect()
}

/// The Jacobian on the tangent space at `z` by central differences of relative step `step`:
/// of `f` in continuous time (`z` one state), of `Phi` when sampled (`z` a history of
/// [`ClosedLoopSystem::slots`] states).
pub fn jacobian(system: &mut ClosedLoopSystem, z: &[f64], step: f64) -> Result<DMatrix<f64>> {
    let (nx, nd) = (system.layout.nx(), system.layout.nd());
    let n = z.len() / nx * nd;
    let scales = coordinate_scales(system, z);
    let plant = system.plant().clone();
    let mut matrix = DMatrix::zeros(n, n);
    let mut direction = DVector::zeros(nd);
    let (mut z_plus, mut z_minus) = (z.to_vec(), z.to_vec());
    let (mut f_plus, mut f_minus) = (DVector::zeros(nd), DVector::zeros(nd));
    let (mut m_plus, mut m_minus) = (z.to_vec(), z.to_vec());
    let mut column = DVector::zeros(n);
    for j in 0..n {
        let h = step * scales[j];
        let slot = (j / nd) * nx..(j / nd + 1) * nx;
        direction.fill(0.0);
        direction[j % nd] = 1.0;
        z_plus.copy_from_slice(z);
        z_minus.copy_from_slice(z);
        sea_plant::retract(
            &plant,
            &z[slot.clone()],
            &direction,
            h,
            &mut z_plus[slot.clone()],
        );
        sea_plant::retract(&plant, &z[slot.clone()], &direction, -h, &mut z_minus[slot]);
        match system.sampling {
            ControlTiming::Continuous => {
                system.vector_field(&z_plus, &mut f_plus)?;
                system.vector_field(&z_minus, &mut f_minus)?;
                column.copy_from(&f_plus);
                column -= &f_minus;
            }
            ControlTiming::ZeroOrderHold { .. } | ControlTiming::MultiRate { .. } => {
                system.period_map(&z_plus, &mut m_plus)?;
                system.period_map(&z_minus, &mut m_minus)?;
                difference_slots(&system.layout, &m_minus, &m_plus, &mut column);
            }
        }
        matrix.column_mut(j).copy_from(&(&column / (2.0 * h)));
    }
    Ok(matrix)
}

/// Newton's method for `f(x) = 0` on the tangent space from `x_start`.
pub fn equilibrium(
    system: &mut ClosedLoopSystem,
    x_start: &[f64],
    options: &LinearizeOptions,
) -> Result<Equilibrium> {
    let nd = system.layout.nd();
    let continuous_sampling = system.sampling;
    system.sampling = ControlTiming::Continuous;
    let result = (|| {
        let plant = system.plant().clone();
        let mut x = x_start.to_vec();
        let mut trial = x.clone();
        let mut f = DVector::zeros(nd);
        let mut f_trial = DVector::zeros(nd);
        system.vector_field(&x, &mut f)?;
        let mut iterations = 0;
        while f.amax() > options.tolerance && iterations < options.max_iterations {
            iterations += 1;
            let a = jacobian(system, &x, options.step)?;
            let Some(dx) = a.lu().solve(&(-&f)) else {
                break;
            };
            // Backtracking: accept the first scale that reduces |f|.
            let mut scale = 1.0;
            let mut accepted = false;
            while scale > 1e-4 {
                sea_plant::retract(&plant, &x, &dx, scale, &mut trial);
                if system.vector_field(&trial, &mut f_trial).is_ok() && f_trial.norm() < f.norm() {
                    accepted = true;
                    break;
                }
                scale *= 0.5;
            }
            if !accepted {
                break;
            }
            std::mem::swap(&mut x, &mut trial);
            std::mem::swap(&mut f, &mut f_trial);
        }
        Ok(Equilibrium {
            converged: f.amax() <= options.tolerance,
            residual: f.amax(),
            state: x,
            iterations,
        })
    })();
    system.sampling = continuous_sampling;
    result
}

/// Growth rate of an eigenvalue [1/s]: `Re lambda`, or `log|mu| / T` for a period map.
fn growth_rate(lambda: Complex<f64>, period: Option<f64>) -> f64 {
    match period {
        None => lambda.re,
        Some(t) => lambda.norm().ln() / t,
    }
}

/// The eigenvalues sorted least stable first, with their growth rates.
fn sorted_spectrum(a: &DMatrix<f64>, period: Option<f64>) -> Result<(Vec<Complex<f64>>, Vec<f64>)> {
    let mut pairs: Vec<(Complex<f64>, f64)> = eigenvalues(a)?
        .into_iter()
        .map(|l| (l, growth_rate(l, period)))
        .collect();
    pairs.sort_by(|p, q| q.1.total_cmp(&p.1).then(q.0.im.total_cmp(&p.0.im)));
    Ok(pairs.into_iter().unzip())
}

/// The dominant states of a mode: entries of the eigenvector made comparable (motor angles and
/// velocities times the transmission ratio, i.e. link side; velocities divided by the mode's
/// rate `max(|lambda|, 1)`, i.e. as position amplitudes), normalised to a largest weight of 1,
/// the `count` largest with weight above 0.05. The mode may be of a delayed history (several
/// slots of `2 (nv + n_e)` coordinates, [`delayed_state_names`]).
pub fn dominant_states(
    mode: &DVector<Complex<f64>>,
    names: &[String],
    ratios: &[f64],
    nv: usize,
    rate: Complex<f64>,
    count: usize,
) -> Vec<(String, f64)> {
    let ne = ratios.len();
    let nd = 2 * (nv + ne);
    let speed = rate.norm().max(1.0);
    let weights: Vec<f64> = (0..mode.len())
        .map(|entry| {
            // The coordinate within its slot of a delayed history.
            let k = entry % nd;
            let motor =
                |offset: usize| (k >= offset && k < offset + ne).then(|| ratios[k - offset]);
            let ratio = motor(nv).or(motor(2 * nv + ne)).unwrap_or(1.0);
            let velocity = if k >= nv + ne { 1.0 / speed } else { 1.0 };
            mode[entry].norm() * ratio * velocity
        })
        .collect();
    let largest = weights
        .iter()
        .cloned()
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut ranked: Vec<(String, f64)> = names
        .iter()
        .zip(&weights)
        .map(|(n, w)| (n.clone(), w / largest))
        .filter(|(_, w)| *w > 0.05)
        .collect();
    ranked.sort_by(|a, b| b.1.total_cmp(&a.1));
    ranked.truncate(count);
    ranked
}

/// Linearises a built closed loop about its equilibrium (see the module doc).
pub fn linearize_system(
    system: &mut ClosedLoopSystem,
    options: &LinearizeOptions,
) -> Result<Linearization> {
    let x_start = system.setup.x0.clone();
    // With a stiffness identification: its estimates converged at the initial state (the
    // plant at rest), then again at the equilibrium they lead to, from which the equilibrium
    // is found once more.
    let identified = system.converge_identification(&x_start)?;
    let mut eq = equilibrium(system, &x_start, options)?;
    if identified && system.converge_identification(&eq.state)? {
        let state = eq.state.clone();
        eq = equilibrium(system, &state, options)?;
    }
    let period = system.period();
    // The history at the equilibrium: every slot at it.
    let slots = system.slots();
    let z = eq.state.repeat(slots);
    let map_residual = match period {
        Some(_) => {
            let mut displacement = DVector::zeros(slots * system.layout.nd());
            system.displacement(&z, &mut displacement)?;
            Some(displacement.amax())
        }
        None => None,
    };
    let matrix = jacobian(system, &z, options.step)?;
    let (values, rates) = sorted_spectrum(&matrix, period)?;
    let step_check = match options.check_step {
        Some(check) => {
            let other = jacobian(system, &z, check)?;
            let (other_values, other_rates) = sorted_spectrum(&other, period)?;
            Some(StepCheck {
                step: check,
                eigenvalue_change: spectrum_distance(&values, &other_values)
                    .max(spectrum_distance(&other_values, &values)),
                least_stable_change: spectrum_distance(&values[..1], &other_values),
                growth_rate_change: (rates[0] - other_rates[0]).abs(),
            })
        }
        None => None,
    };
    let least = values[0];
    let least_stable_rate = match period {
        None => least,
        Some(t) => least.ln() / t,
    };
    let mode = eigenvector(&matrix, least);
    let names = delayed_state_names(
        &state_names(&system.setup.model.joint_names, &system.setup.elastic_names),
        slots,
    );
    let ratios: Vec<f64> = system
        .plant()
        .actuation
        .elastic
        .iter()
        .map(|p| p.ratio)
        .collect();
    let dominant = dominant_states(
        &mode,
        &names,
        &ratios,
        system.layout.nv,
        least_stable_rate,
        options.dominant_count,
    );
    Ok(Linearization {
        sampling: system.sampling,
        time: options.time,
        map_residual,
        growth_rate: rates[0],
        stable: rates[0] < 0.0,
        eigenvalues: values,
        growth_rates: rates,
        least_stable_rate,
        state_names: names,
        least_stable_mode: mode,
        dominant_states: dominant,
        matrix,
        step: options.step,
        step_check,
        equilibrium: eq,
    })
}

/// The closed loop of `scenario` with the references frozen at `options.time`, with its
/// sensing delay (`sensing.delay_inner_periods`, refused in continuous time). An external
/// wrench observer (`controller.external_wrench = "observed"`) is refused: its estimate is
/// not a state of the map.
pub fn closed_loop_system(
    scenario: &Scenario,
    options: &LinearizeOptions,
) -> Result<ClosedLoopSystem> {
    if scenario.controller.wrench_observer.kind != ExternalWrench::None {
        return Err(Error::invalid(
            "controller.external_wrench",
            "the period map has no state for the observer's estimate (analyse the loop with \
             \"none\")",
            scenario.controller.wrench_observer.kind.name(),
        ));
    }
    let setup = sea_scenario::build(scenario)?;
    let sampling = match options.sampling {
        Some(sampling) => sampling,
        None => ControlTiming::of_scenario(scenario),
    };
    let method = scenario.plant.method;
    let mut system =
        ClosedLoopSystem::new(setup, options.time, sampling, scenario.plant.dt, method)?;
    if scenario.controller.sampling == sea_scenario::Sampling::MultiRate {
        let joint_loop = scenario.controller.joint_loop(system.controller());
        let identifier = scenario
            .controller
            .stiffness_identifier(system.controller(), joint_loop.estimates());
        system.set_joint_loop(Some(joint_loop));
        let source = scenario.controller.identification_wrenches;
        system.set_identifier(identifier.map(|identifier| (identifier, source)));
    }
    system.set_delay(scenario.sensing.delay_inner_periods)?;
    system.set_w_refresh_steps(scenario.plant.w_refresh_steps);
    Ok(system)
}

/// Linearises the closed loop of `scenario` with the references frozen at `t` (default 0), in
/// the scenario's sampling, with the default options.
pub fn linearize(scenario: &Scenario, t: Option<f64>) -> Result<Linearization> {
    linearize_with(
        scenario,
        &LinearizeOptions {
            time: t.unwrap_or(0.0),
            ..Default::default()
        },
    )
}

/// [`linearize`] with explicit options.
pub fn linearize_with(scenario: &Scenario, options: &LinearizeOptions) -> Result<Linearization> {
    let mut system = closed_loop_system(scenario, options)?;
    linearize_system(&mut system, options)
}
