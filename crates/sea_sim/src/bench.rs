//! Native benchmarks of the dynamics algorithms (`sea-sim bench`).
//!
//! Each algorithm runs on a fixed set of random states (seeded), in batches; the figure is the
//! median over batches of the mean time per call, in microseconds. Medians of batch means are
//! robust to the scheduler noise of shared machines; compare ratios measured in one run.

use sea_ctrl::qp::QpSolver;
use sea_dyn::sample::{random_configuration, random_velocity, Lcg};
use sea_dyn::{Actuation, Actuator, Data, ElasticParameters, Model};
use sea_plant::{Method, Plant, PlantData};
use std::collections::HashMap;
use std::hint::black_box;
use std::time::Instant;

/// Number of random states cycled through.
const STATES: usize = 64;

/// Median over `batches` of the mean microseconds per call of `f(state_index)`.
pub fn median_us(batches: usize, calls_per_batch: usize, mut f: impl FnMut(usize)) -> f64 {
    for k in 0..calls_per_batch {
        f(k % STATES); // warm-up
    }
    let mut means: Vec<f64> = (0..batches)
        .map(|_| {
            let start = Instant::now();
            for k in 0..calls_per_batch {
                f(k % STATES);
            }
            start.elapsed().as_secs_f64() * 1e6 / calls_per_batch as f64
        })
        .collect();
    means.sort_by(|a, b| a.total_cmp(b));
    means[means.len() / 2]
}

/// Results of [`bench_dynamics`], microseconds per call.
pub struct DynamicsBench {
    /// (JSON key, median microseconds) in report order.
    pub figures: Vec<(&'static str, f64)>,
    /// Frame used for the frame Jacobian figures.
    pub frame: String,
}

/// Benchmarks the dynamics algorithms on `model`.
pub fn bench_dynamics(model: &Model, batches: usize, calls_per_batch: usize) -> DynamicsBench {
    let mut rng = Lcg::new(42);
    let qs: Vec<Vec<f64>> = (0..STATES)
        .map(|_| random_configuration(model, &mut rng))
        .collect();
    let nus: Vec<Vec<f64>> = (0..STATES)
        .map(|_| random_velocity(model, &mut rng))
        .collect();
    let nudots: Vec<Vec<f64>> = (0..STATES)
        .map(|_| random_velocity(model, &mut rng))
        .collect();
    let frame_name = if model.frame_id("l_sole").is_ok() {
        "l_sole".to_string()
    } else {
        model
            .frames
            .last()
            .map(|f| f.name.clone())
            .unwrap_or_default()
    };
    let frame = model.frame_id(&frame_name).unwrap_or(0);
    let mut data = Data::new(model);
    let mut run = |f: &mut dyn FnMut(&mut Data, usize)| {
        median_us(batches, calls_per_batch, |k| f(&mut data, k))
    };
    let figures = vec![
        (
            "rnea_us",
            run(&mut |d, k| {
                black_box(sea_dyn::rnea(model, d, &qs[k], &nus[k], &nudots[k]));
            }),
        ),
        (
            "crba_us",
            run(&mut |d, k| {
                black_box(sea_dyn::crba(model, d, &qs[k]));
            }),
        ),
        (
            "centroidal_momentum_matrix_us",
            run(&mut |d, k| {
                black_box(sea_dyn::centroidal_momentum_matrix(model, d, &qs[k]));
            }),
        ),
        (
            "frame_jacobian_us",
            run(&mut |d, k| {
                black_box(sea_dyn::frame_jacobian(model, d, &qs[k], frame));
            }),
        ),
        (
            "frame_jacobian_dot_v_us",
            run(&mut |d, k| {
                black_box(sea_dyn::frame_jacobian_dot_v(
                    model, d, &qs[k], &nus[k], frame,
                ));
            }),
        ),
    ];
    let mut figures = figures;
    if let Some(plant_figures) = bench_plant(model, batches, calls_per_batch / 10 + 1) {
        figures.extend(plant_figures);
    }
    DynamicsBench {
        figures,
        frame: frame_name,
    }
}

/// The benchmark scenario: the iCub of `urdf` on both soles, SEA plant and controller, a 1 cm
/// CoM sinusoid at 0.25 Hz; `controller` and `simulation` are TOML lines of the
/// `[controller]` and `[simulation]` tables.
fn two_feet_scenario(
    urdf: &str,
    controller: &str,
    simulation: &str,
) -> Option<crate::scenario::Scenario> {
    two_feet_scenario_on(urdf, "", controller, simulation)
}

/// [`two_feet_scenario`] with `plant`, the TOML lines of its `[plant]` table.
fn two_feet_scenario_on(
    urdf: &str,
    plant: &str,
    controller: &str,
    simulation: &str,
) -> Option<crate::scenario::Scenario> {
    let text = format!(
        "[robot]\nurdf = {urdf:?}\ncontacts = [\"l_sole\", \"r_sole\"]\ninitial_posture = \"two_feet\"\n\
         [reference]\ncom_origin = \"initial\"\ncom_amplitude = 0.01\ncom_frequency = 0.25\n\
         [plant]\n{plant}\n[controller]\n{controller}\n[simulation]\n{simulation}\n"
    );
    crate::scenario::Scenario::from_toml(&text, &[], std::path::Path::new(".")).ok()
}

/// `controller_tick_us`: one tick of the SEA controller on the iCub standing on two feet (all
/// model terms, the QP and the SEA mapping), as it runs in the closed loop;
/// `controller_tick_clarabel_us`, the same tick with Clarabel solving the QP every time (no
/// shortcut through the minimiser without inequalities); `controller_tick_active_set_us`, the
/// same with the active-set solver every time. `None` when `urdf` is not an iCub with the
/// paper's 25 joints and both soles.
pub fn bench_controller(
    urdf: &str,
    batches: usize,
    calls_per_batch: usize,
) -> Option<Vec<(&'static str, f64)>> {
    let mut figures = Vec::new();
    for (key, qp) in [
        ("controller_tick_us", TickQp::Default),
        (
            "controller_tick_clarabel_us",
            TickQp::Every(QpSolver::Clarabel),
        ),
        (
            "controller_tick_active_set_us",
            TickQp::Every(QpSolver::ActiveSet),
        ),
    ] {
        let mut ticks = TickBench::two_feet(urdf, qp)?;
        let mut ok = true;
        let time = median_us(batches, calls_per_batch, |k| ok &= ticks.tick(k));
        figures.push((key, ok.then_some(time)?));
    }
    Some(figures)
}

/// `closed_loop_second_ms`: wall time [ms] of one simulated second of the closed loop (the
/// two-feet scenario of [`bench_controller`], plant step 1 ms, controller at 1 kHz with
/// zero-order hold, no recording); `closed_loop_second_continuous_ms`: the same with the
/// controller evaluated at every integrator stage (the paper's continuous-time setting);
/// `closed_loop_second_multi_rate_ms`: the robot's rates (`multi_rate`: the rigid model's QP
/// at 100 Hz, the joint torque loops at 1 kHz); `closed_loop_second_multi_rate_unilateral_ms`,
/// the same with the feet on the ground (unilateral contacts, joint stops).
/// Median over `runs` runs; `None` when `urdf` is not the paper's iCub or a run diverges.
pub fn bench_closed_loop(urdf: &str, runs: usize) -> Option<Vec<(&'static str, f64)>> {
    let mut figures = Vec::new();
    let multi_rate = "rate_hz = 100.0\nsampling = \"multi_rate\"\ninner_rate_hz = 1000.0\n\
                      kind = \"rigid\"\nreflected_inertia = false";
    let unilateral = "contact_model = \"unilateral\"";
    for (key, plant, controller) in [
        (
            "closed_loop_second_ms",
            "",
            "rate_hz = 1000.0\nsampling = \"zero_order_hold\"",
        ),
        (
            "closed_loop_second_continuous_ms",
            "",
            "rate_hz = 1000.0\nsampling = \"continuous\"",
        ),
        ("closed_loop_second_multi_rate_ms", "", multi_rate),
        (
            "closed_loop_second_multi_rate_unilateral_ms",
            unilateral,
            multi_rate,
        ),
    ] {
        let scenario = two_feet_scenario_on(urdf, plant, controller, "duration_s = 1.0")?;
        figures.push((key, median_run_ms(&scenario, runs).ok()?));
    }
    Some(figures)
}

/// The median wall time [ms] of `runs` runs (at least one) of `scenario`, nothing recorded. An
/// error when a run fails or does not complete (its status, time and reason named).
fn median_run_ms(scenario: &crate::scenario::Scenario, runs: usize) -> crate::Result<f64> {
    let mut wall_ms = Vec::with_capacity(runs.max(1));
    for _ in 0..runs.max(1) {
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let summary = crate::closed_loop::run_with_sinks(scenario, &mut [], &cancel, |_, _| {})?;
        if !summary.completed() {
            return Err(crate::Error::config(
                "simulation",
                format!(
                    "the benchmark's run did not complete: {} at {:.3} s ({})",
                    summary.status, summary.duration_s, summary.reason
                ),
            ));
        }
        wall_ms.push(summary.wall_time_s * 1e3);
    }
    wall_ms.sort_by(|a, b| a.total_cmp(b));
    Ok(wall_ms[wall_ms.len() / 2])
}

/// `controller_tick_us` of a scenario file: one tick of the controller of `ticks`
/// ([`TickBench::try_new`]: as the scenario sets it up, its rate, sampling, QP and walking; a
/// multi-rate controller's whole-body tick) at small random perturbations of its initial
/// state, the median of `batches` batch means. An error when a tick fails.
pub fn bench_scenario_controller(
    ticks: &mut TickBench,
    batches: usize,
    calls_per_batch: usize,
) -> crate::Result<f64> {
    let mut failed = None;
    let time = median_us(batches, calls_per_batch, |k| {
        if !ticks.tick(k) {
            failed.get_or_insert(k % STATES);
        }
    });
    match failed {
        None => Ok(time),
        Some(state) => Err(crate::Error::config(
            "controller",
            format!("the controller failed on the benchmark's perturbed state {state}"),
        )),
    }
}

/// `scenario_second_ms`: the wall time [ms] of the first simulated second of the scenario at
/// `path` with `overrides` (its `simulation.duration_s` set to 1 s, nothing recorded), the
/// median over `runs` runs. An error when a run does not complete (its reason named).
pub fn bench_scenario_second(
    path: &std::path::Path,
    overrides: &[(String, String)],
    runs: usize,
) -> crate::Result<f64> {
    let mut overrides = overrides.to_vec();
    overrides.push(("simulation.duration_s".into(), "1.0".into()));
    let scenario = crate::scenario::Scenario::from_file(path, &overrides)?;
    median_run_ms(&scenario, runs)
}

/// How the benchmark tick solves its QP.
#[derive(Clone, Copy, Debug)]
pub enum TickQp {
    /// As in the closed loop: the minimiser without inequalities when feasible, else the
    /// default solver.
    Default,
    /// This solver on every tick (`qp_unconstrained_first = false`).
    Every(QpSolver),
}

/// A controller of the two-feet benchmark scenario and the states it is ticked on (also used by
/// the criterion benches).
pub struct TickBench {
    setup: crate::closed_loop::Setup,
    layout: sea_dyn::StateLayout,
    states: Vec<Vec<f64>>,
    reference: sea_ctrl::references::ComSample,
    s_desired: Vec<f64>,
    /// The controller's output, refilled by every tick (as in the closed loop).
    output: sea_ctrl::controller::ControlOutput,
}

impl TickBench {
    /// The controller of `scenario` and `STATES` small random perturbations of its initial
    /// state. `None` when the scenario does not build ([`Self::try_new`] says why).
    pub fn new(scenario: &crate::scenario::Scenario) -> Option<TickBench> {
        Self::try_new(scenario).ok()
    }

    /// [`Self::new`], the error of a scenario that does not build.
    pub fn try_new(scenario: &crate::scenario::Scenario) -> crate::Result<TickBench> {
        let setup = crate::closed_loop::build(scenario)?;
        let layout = setup.plant.layout();
        let mut s_desired = vec![0.0; setup.model.n_joints()];
        setup.posture.at(0.0, &mut s_desired);
        let mut rng = Lcg::new(7);
        // Small random velocities around the standing state, so the QP is warm but not trivial.
        let states: Vec<Vec<f64>> = (0..STATES)
            .map(|_| {
                let mut x = setup.x0.clone();
                for v in &mut x[layout.nu_offset()..layout.nu_offset() + layout.nv] {
                    *v = 0.01 * rng.next_signed();
                }
                x
            })
            .collect();
        let reference = setup.com_reference.sample(1.0);
        let output = setup.controller.new_output();
        Ok(TickBench {
            output,
            setup,
            layout,
            states,
            reference,
            s_desired,
        })
    }

    /// The two-feet benchmark scenario of `urdf` with the QP path `qp`.
    pub fn two_feet(urdf: &str, qp: TickQp) -> Option<TickBench> {
        let controller = match qp {
            TickQp::Default => String::new(),
            TickQp::Every(solver) => format!(
                "qp_unconstrained_first = false\nqp_solver = {:?}",
                solver.name()
            ),
        };
        TickBench::new(&two_feet_scenario(urdf, &controller, "")?)
    }

    /// What the scenario's build warns of (its URDF's doubtful elements, a walking command the
    /// step limits clip), one message each, as `sea-sim run` prints them.
    pub fn warnings(&self) -> &[String] {
        &self.setup.warnings
    }

    /// The scenario's robot model.
    pub fn model(&self) -> &Model {
        &self.setup.model
    }

    /// One tick at state `k % STATES`; `false` when the controller failed.
    pub fn tick(&mut self, k: usize) -> bool {
        self.setup
            .controller
            .compute_into(
                &self.states[k % STATES],
                &self.layout,
                &self.reference,
                &self.s_desired,
                &mut self.output,
            )
            .is_ok()
    }
}

/// The paper's plant: every joint a SEA (docs/references.md#paper-simulation-results), both
/// soles in contact, standing at the neutral posture with the springs preloaded against
/// gravity. `None` without `l_sole` and `r_sole` frames.
pub fn standing_sea_plant(model: &Model) -> Option<(Plant, Vec<f64>)> {
    let (left, right) = (
        model.frame_id("l_sole").ok()?,
        model.frame_id("r_sole").ok()?,
    );
    let mut q = model.neutral();
    let mut data = Data::new(model);
    sea_dyn::forward_kinematics(model, &mut data, &q);
    let sole_height = sea_dyn::frame_placement(model, &data, left).translation.z;
    let _ = right;
    q[2] = -sole_height;
    let sea = ElasticParameters::paper_icub();
    let actuation = Actuation::new(model, Actuator::Elastic(sea), &HashMap::new()).ok()?;
    let mut plant = Plant::new(model.clone(), actuation);
    plant
        .set_contacts(&["l_sole".to_string(), "r_sole".to_string()], &q)
        .ok()?;
    let gravity = sea_dyn::gravity_forces(model, &mut data, &q).clone();
    let theta = plant
        .preloaded_motor_angles(&q, &gravity.as_slice()[6..])
        .ok()?;
    let nu = vec![0.0; model.nv()];
    let x = plant.make_state(&q, &nu, Some(&theta), None).ok()?;
    Some((plant, x))
}

/// The motor input of the plant benchmarks at state `x` of [`standing_sea_plant`]: 1 % of the
/// joint gravity torques (the springs are preloaded; the input only has to be non-trivial).
pub fn standing_motor_input(model: &Model, x: &[f64]) -> Vec<f64> {
    let mut data = Data::new(model);
    let gravity = sea_dyn::gravity_forces(model, &mut data, &x[..model.nq()]);
    (0..model.n_joints())
        .map(|j| 0.01 * gravity[6 + j])
        .collect()
}

/// The plant of [`standing_sea_plant`] with its feet on the ground: unilateral contacts at the
/// soles' corners (the paper's iCub sole) sized to sink 0.5 mm, joint stops, the ground at the
/// soles.
pub fn standing_sea_plant_on_ground(model: &Model) -> Option<(Plant, Vec<f64>)> {
    let (mut plant, x) = standing_sea_plant(model)?;
    let surface = sea_dyn::ContactSurface::default();
    let corners = sea_plant::UnilateralContacts::rectangle_corners(surface.foot_x, surface.foot_y);
    let gravity = model.gravity.norm();
    let law =
        sea_plant::CompliantContact::for_weight(model.total_mass() * gravity, 8, 5e-4, gravity);
    let ground = sea_plant::Ground::flat(5e-4, surface.friction).ok()?;
    plant
        .set_unilateral_contacts(ground, law, vec![corners.clone(), corners])
        .ok()?;
    plant.joint_stops = Some(sea_plant::JointStops::default());
    Some((plant, x))
}

/// `plant_dynamics_us` (one evaluation of the SEA plant on two feet) and `sim_step_us` (one
/// ROS2 step, dt = 1 ms, preparing its own `W`), on the standing iCub with motor torques
/// balancing gravity; `sim_step_unilateral_us`, the step with the feet on the ground
/// ([`standing_sea_plant_on_ground`]); the `_shared_w` figures are the same steps with
/// [`shared_w_steps`] steps sharing one `W`, as every scenario steps (`plant.w_refresh_steps`'s
/// default): their mean over a whole sharing cycle.
fn bench_plant(
    model: &Model,
    batches: usize,
    calls_per_batch: usize,
) -> Option<Vec<(&'static str, f64)>> {
    let (plant, x) = standing_sea_plant(model)?;
    let mut pd = PlantData::new(&plant);
    let u = standing_motor_input(model, &x);
    let dynamics = median_us(batches, calls_per_batch, |_| {
        black_box(sea_plant::evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).is_ok());
    });
    let timing = (batches, calls_per_batch);
    let step = median_step_us(&plant, &x, &u, 1, timing);
    let step_shared = median_step_us(&plant, &x, &u, shared_w_steps(), timing);
    let (ground_plant, x) = standing_sea_plant_on_ground(model)?;
    let on_ground = median_step_us(&ground_plant, &x, &u, 1, timing);
    let on_ground_shared = median_step_us(&ground_plant, &x, &u, shared_w_steps(), timing);
    Some(vec![
        ("plant_dynamics_us", dynamics),
        ("sim_step_us", step),
        ("sim_step_shared_w_us", step_shared),
        ("sim_step_unilateral_us", on_ground),
        ("sim_step_unilateral_shared_w_us", on_ground_shared),
    ])
}

/// Median microseconds of one ROS2 step (dt = 1 ms) of `plant` from `x` with `u` held, with
/// `w_refresh_steps` steps sharing one `W`; `timing` is `(batches, calls per batch)`.
fn median_step_us(
    plant: &Plant,
    x: &[f64],
    u: &[f64],
    w_refresh_steps: usize,
    (batches, calls_per_batch): (usize, usize),
) -> f64 {
    let mut pd = PlantData::new(plant);
    pd.integrator.set_w_refresh_steps(w_refresh_steps);
    let mut x_next = x.to_vec();
    median_us(batches, calls_per_batch, |_| {
        black_box(sea_plant::step(plant, &mut pd, x, u, 1e-3, Method::Ros2, &mut x_next).is_ok());
    })
}

/// Steps sharing one `W` in the `_shared_w` figures: `plant.w_refresh_steps`' default.
fn shared_w_steps() -> usize {
    crate::scenario::PlantConfig::default().w_refresh_steps
}
