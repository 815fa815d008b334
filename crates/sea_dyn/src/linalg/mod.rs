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

/// `a * b + c`: one fused multiply-add (a single rounding) when the build target has it in
/// hardware (x86-64 with FMA, which `target-cpu=native` in `.cargo/config.toml` enables on any
/// x86-64 of the last decade; every aarch64), else the plain product and sum (a software `fma`
/// would be a slow library call). The kernels' inner loops are chains of these, so fusing
/// halves their instructions and the latency of their chains.
#[inline(always)]
pub fn mul_add(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(any(target_feature = "fma", target_arch = "aarch64"))]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(any(target_feature = "fma", target_arch = "aarch64")))]
    {
        a * b + c
    }
}

pub mod dense;
pub mod tree_factor;

#[cfg(test)]
mod tests {
    use super::mul_add;

    /// Fused where the target has it, one rounding: `(1 + e)(1 - e) - 1` is `-e^2` exactly,
    /// which the rounded product (1) loses.
    #[test]
    fn mul_add_rounds_once_where_the_target_fuses() {
        let e = 2f64.powi(-30);
        let fused = cfg!(any(target_feature = "fma", target_arch = "aarch64"));
        let expected = if fused { -e * e } else { 0.0 };
        assert_eq!(mul_add(1.0 + e, 1.0 - e, -1.0), expected);
        assert_eq!(mul_add(2.0, 3.0, 4.0), 10.0);
    }
}
