//! Linear algebra: allocation-free dense helpers and the tree-sparse `L^T L` factorisation of
//! the mass matrix (no fill-in along the kinematic tree).

/// Calls `$body` with the size `$k` (right-hand sides, or a small matrix's order) as a literal
/// for the common contact sizes (one foot: 6, two feet: 12), so that the inlined kernels get
/// fixed-length inner loops, and as a runtime value otherwise. Defined before the modules so
/// that they see it.
macro_rules! with_fixed_width {
    ($k:expr, |$width:ident| $body:expr) => {
        match $k {
            6 => {
                let $width = 6;
                $body
            }
            12 => {
                let $width = 12;
                $body
            }
            other => {
                let $width = other;
                $body
            }
        }
    };
}

pub mod dense;
pub mod tree_factor;
