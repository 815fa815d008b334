//! An identification excitation: a sinusoidal torque added for a while to the desired torques
//! of chosen elastic joints in the joint loops, so that joints the balancing task leaves
//! unloaded carry torques the stiffness identification ([`crate::stiffness_id`]) can see.
//!
//! Why (docs/findings/pushes.md): the identification learns a joint's stiffness
//! from the torque the model says it carries against the deflection the encoders measure, and
//! a joint that carries less than `K_S^0 delta_0` keeps its prior. Standing on two feet the
//! iCub's ankle rolls carry almost no torque (0.35 Nm), so an estimate off by x2 stays off
//! (x1.2 and x1.9 after 3 s), and a sideways push, the first thing that loads them, meets a
//! torque loop whose gain `K_S / K_S^` is 1/2. Robots are identified with excitation for this
//! reason (a signal that is persistently exciting); here the joint loop adds
//!
//! `tau_d,e += a_e sin(2 pi f t)` for `0 <= t < t_end`
//!
//! with one amplitude `a_e` [Nm] per excited joint, `t_end` the first whole cycle at or after
//! the duration asked for (so the torque ends at zero, without a step). With the same sign on
//! the two legs' mirrored joints the torques are internal: the feet take them as moments and
//! the CoM hardly moves (measured on the iCub: less than a micrometre with 1 Nm on the legs'
//! roll and yaw joints; with 2 Nm of opposite signs on the ankle rolls the robot sways by
//! 2 cm). The excitation is an input, not a state: it does not change the period map's
//! eigenvalues.

use std::collections::BTreeMap;

/// The excitation as a user sets it ([`IdentificationExcitation::new`] takes its amplitudes
/// per elastic joint once the names are resolved). With the `serde` feature, the keys
/// `identification_excitation_nm`, `identification_excitation_hz` and
/// `identification_excitation_s` of a scenario's `[controller]`, each bounded as it is read
/// (`sea_dyn::bounded`).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ExcitationSettings {
    /// `multi_rate`: per elastic joint name, the amplitude `a_e` [Nm] of a sinusoid added to
    /// its desired torque in the joint loop from the start of the run, so that the
    /// identification sees joints the task leaves unloaded (`sea_ctrl::excitation`; e.g. the
    /// legs' roll and yaw joints on two feet, the same sign on both legs; default none).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_excitation_nm",
            deserialize_with = "sea_dyn::bounded::Finite::read_map"
        ),
        schemars(with = "BTreeMap<String, sea_dyn::bounded::Finite>")
    )]
    pub amplitudes_nm: BTreeMap<String, f64>,
    /// `identification_excitation_nm`: the sinusoid's frequency `f` [Hz] (default 1 Hz).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_excitation_hz",
            deserialize_with = "sea_dyn::bounded::Positive::read"
        ),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub frequency_hz: f64,
    /// `identification_excitation_nm`: how long it lasts [s], rounded up to whole cycles
    /// (default 3 s).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_excitation_s",
            deserialize_with = "sea_dyn::bounded::NonNegative::read"
        ),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub duration_s: f64,
}

impl Default for ExcitationSettings {
    /// No excitation; when one is set, 1 Hz for 3 s.
    fn default() -> Self {
        Self {
            amplitudes_nm: BTreeMap::new(),
            frequency_hz: 1.0,
            duration_s: 3.0,
        }
    }
}

/// The sinusoid added to the joint loops' desired torques (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct IdentificationExcitation {
    /// Amplitude `a_e` per elastic joint (n_e) [Nm]; 0 for a joint not excited.
    amplitudes: Vec<f64>,
    /// Frequency `f` [Hz].
    frequency_hz: f64,
    /// End `t_end` [s]: the first whole cycle at or after the duration asked for.
    end_s: f64,
}

impl IdentificationExcitation {
    /// The excitation with `amplitudes` (n_e, [Nm]) at `frequency_hz` (positive) for at least
    /// `duration_s` [s] (ended at the first whole cycle at or after it).
    pub fn new(amplitudes: Vec<f64>, frequency_hz: f64, duration_s: f64) -> Self {
        assert!(frequency_hz > 0.0, "excitation frequency must be positive");
        let end_s = (duration_s * frequency_hz).ceil() / frequency_hz;
        Self {
            amplitudes,
            frequency_hz,
            end_s,
        }
    }

    /// The excitation of `settings` with `amplitudes` (n_e, [Nm]): its amplitudes by name
    /// resolved to the elastic joints.
    pub fn from_settings(amplitudes: Vec<f64>, settings: &ExcitationSettings) -> Self {
        Self::new(amplitudes, settings.frequency_hz, settings.duration_s)
    }

    /// When the excitation ends [s] (a whole number of cycles).
    pub fn end_s(&self) -> f64 {
        self.end_s
    }

    /// Adds the excitation at time `time` [s] to `torques` (n_e, the joint loops' desired
    /// torques [Nm]); nothing outside `[0, t_end)`.
    pub fn add_to(&self, time: f64, torques: &mut [f64]) {
        if !(0.0..self.end_s).contains(&time) {
            return;
        }
        let phase = (2.0 * std::f64::consts::PI * self.frequency_hz * time).sin();
        for (torque, amplitude) in torques.iter_mut().zip(&self.amplitudes) {
            *torque += amplitude * phase;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sinusoid_of_whole_cycles_on_the_excited_joints_only() {
        let excitation = IdentificationExcitation::new(vec![2.0, 0.0, -1.0], 1.0, 2.6);
        assert_eq!(excitation.end_s(), 3.0);
        let at = |time: f64| {
            let mut torques = vec![10.0; 3];
            excitation.add_to(time, &mut torques);
            torques
        };
        let quarter = at(0.25);
        assert!((quarter[0] - 12.0).abs() < 1e-12, "{quarter:?}");
        assert_eq!(quarter[1], 10.0);
        assert!((quarter[2] - 9.0).abs() < 1e-12, "{quarter:?}");
        assert!((at(2.75)[0] - 8.0).abs() < 1e-12);
        for outside in [-0.25, 3.0, 3.25] {
            assert_eq!(at(outside), vec![10.0; 3], "at {outside} s");
        }
    }
}
