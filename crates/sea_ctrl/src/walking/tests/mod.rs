//! Tests of the walking planner: settings and errors, footsteps, the DCM and CoM reference,
//! swing soles, the contact schedule, push-recovery steps.

mod capture;
mod dcm;
mod figures;
mod footsteps;
mod gait;
mod phase;
#[cfg(feature = "serde")]
mod serde;
mod settings;
mod step_timing;
mod swing;

use super::footstep::Stance;
use super::lip::Lip;
use super::settings::WalkingSettings;
use nalgebra::Vector2;

/// The default settings walking `steps` steps at the given velocities.
fn walking(steps: usize, forward: f64, sideways: f64, turning: f64) -> WalkingSettings {
    let mut settings = WalkingSettings::default();
    settings.command.steps = Some(steps);
    settings.command.forward_velocity = forward;
    settings.command.sideways_velocity = sideways;
    settings.command.turning_velocity = turning;
    settings
}

/// Feet side by side at the origin facing +x, the nominal width apart.
fn standing(settings: &WalkingSettings) -> Stance {
    Stance::side_by_side(Vector2::zeros(), 0.0, settings.nominal_width)
}

/// The pendulum of the settings under 9.81 m/s^2.
fn lip(settings: &WalkingSettings) -> Lip {
    settings.lip(9.81).expect("valid height")
}

/// A seeded uniform sampler in [0, 1) (xorshift), for reproducible loops.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `|a - b| <= tol`, with a message.
#[track_caller]
fn assert_close(a: Vector2<f64>, b: Vector2<f64>, tol: f64, what: &str) {
    let error = (a - b).norm();
    assert!(
        error <= tol,
        "{what}: {a:?} vs {b:?} (error {error:e} > {tol:e})"
    );
}
