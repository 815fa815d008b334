//! The integration tests of sea_sim, one module per file of this folder.
//!
//! They are one test binary: each release test binary is linked with thin LTO on its own
//! (about a minute on two cores), so one binary per crate keeps the test build short. Run one
//! file's tests with its module path as the filter,
//! e.g. `cargo test --release -p sea_sim --test integration walking_mcap::`.
//! `no_alloc` stays a binary of its own: its counting global allocator would replace the
//! allocator of every test here.

mod support;

mod analysis;
mod bench_cli;
mod cli;
mod cli_docs;
mod closed_loop;
mod contact_check_mcap;
mod controller;
mod errors;
mod ground;
mod impacts;
mod init;
mod live;
mod margin_island;
mod mcap_log;
mod mcap_meshes;
mod model_errors;
mod multi_rate;
mod proptest_scenario;
mod push;
mod push_mcap;
mod qp_agreement;
mod schema;
mod sensing;
mod stiffness_identification;
mod study_signals;
mod summary_keys;
mod sweep;
mod template_walk;
mod test_layout;
mod walk_push;
mod walking_impacts;
mod walking_mcap;
