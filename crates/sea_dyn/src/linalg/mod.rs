//! Linear algebra: allocation-free dense helpers and the tree-sparse `L^T L` factorisation of
//! the mass matrix (no fill-in along the kinematic tree).

pub mod dense;
pub mod tree_factor;
