//! The integration tests of sea_scenario, one module per file of this folder.
//!
//! They are one test binary: each release test binary is linked with thin LTO on its own
//! (about a minute on two cores), so one binary per crate keeps the test build short. Run one
//! file's tests with its module path as the filter,
//! e.g. `cargo test --release -p sea_scenario --test integration walking::`.

mod actuators;
mod fast_walks;
mod ground;
mod messages;
mod stepping;
mod walking;
