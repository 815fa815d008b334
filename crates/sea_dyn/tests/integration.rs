//! The integration tests of sea_dyn, one module per file of this folder.
//!
//! They are one test binary: each release test binary is linked with thin LTO on its own
//! (about a minute on two cores), so one binary per crate keeps the test build short. Run one
//! file's tests with its module path as the filter,
//! e.g. `cargo test --release -p sea_dyn --test integration urdf_errors::`.
//! `no_alloc` stays a binary of its own: its counting global allocator would replace the
//! allocator of every test here.

mod common;

mod physics;
mod tree_factor;
mod urdf_errors;
mod urdf_limits;
