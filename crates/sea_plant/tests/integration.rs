//! The integration tests of sea_plant, one module per file of this folder.
//!
//! They are one test binary: each release test binary is linked with thin LTO on its own
//! (about a minute on two cores), so one binary per crate keeps the test build short. Run one
//! file's tests with its module path as the filter,
//! e.g. `cargo test --release -p sea_plant --test integration unilateral::`.

mod support;

mod conservation;
mod contact;
mod external_wrench;
mod feedback_step;
mod integrators;
mod unilateral;
