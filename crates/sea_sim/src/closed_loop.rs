//! The closed loop at its former path: `sea_loop`'s items, with the scenario's `run`
//! conveniences (`sea_sim::scenario::run`) and building.

pub use crate::scenario::run::{run, run_setup_with_sinks, run_with_sinks};
pub use crate::scenario::{build, Setup};
pub use sea_loop::{
    contact_check, equal_steps, impacts, inner_ticks, ContactCheckEvent, ContactConstraint,
    Divergence, DivergenceBounds, Fall, FallSummary, Impact, ImpactKind, LoopSettings, OwnedSample,
    RecordSink, RunEnd, RunInfo, RunRecord, RunScene, RunTotals, RunningStatistics, Sample,
    Sampling, Schedule, Summary, VerdictChange, WrenchCheck, NON_SCALAR_FIELDS,
};
