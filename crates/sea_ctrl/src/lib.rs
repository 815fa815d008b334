//! `sea_ctrl`: momentum-based balancing controllers, scenarios, logging and the `sea-sim`
//! binary. Today it holds the native benchmarks; the controllers build on `sea_dyn`.

#![forbid(unsafe_code)]

pub mod bench;
