//! The rigid-body algorithms, one file each with its equation in the header. Each writes into
//! [`crate::Data`] and allocates nothing.

pub mod centroidal;
pub mod crba;
pub mod jacobian;
pub mod kinematics;
pub mod rnea;
pub mod split;
