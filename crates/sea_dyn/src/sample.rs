//! Deterministic random states for tests and benchmarks (no external generator, so runs are
//! repeatable on every machine).

use crate::model::Model;
/// A small deterministic generator (PCG-style LCG), so runs are repeatable without a crate.
pub struct Lcg(u64);

impl Lcg {
    /// Generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// Uniform in [-1, 1).
    pub fn next_signed(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A random configuration: base in a 1 m box, random unit quaternion, joints in [-1, 1] rad.
pub fn random_configuration(model: &Model, rng: &mut Lcg) -> Vec<f64> {
    let mut q: Vec<f64> = (0..model.nq()).map(|_| rng.next_signed()).collect();
    let norm = q[3..7].iter().map(|c| c * c).sum::<f64>().sqrt();
    q[3..7].iter_mut().for_each(|c| *c /= norm);
    q
}

/// A random velocity-sized vector with entries in [-1, 1].
pub fn random_velocity(model: &Model, rng: &mut Lcg) -> Vec<f64> {
    (0..model.nv()).map(|_| rng.next_signed()).collect()
}
