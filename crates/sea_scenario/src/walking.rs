//! `[walking]` on a built scenario: the legs' reach checked against the step length, and the
//! controller set to walk (`sea_ctrl::MomentumController::set_walking`).

use crate::error::{Error, Result};
use crate::Scenario;
use sea_ctrl::controller::MomentumController;
use sea_dyn::{Data, FrameId, Model};

/// The straight length of the leg of `sole` (the sum of the distances between its joints'
/// origins from the hip, the first joint below the base, down to the sole) and the hip's
/// height above the sole at `q` [m].
pub fn leg_length_and_hip_height(model: &Model, q: &[f64], sole: FrameId) -> (f64, f64) {
    let mut data = Data::new(model);
    sea_dyn::forward_kinematics(model, &mut data, q);
    let world_p_sole = sea_dyn::frame_placement(model, &data, sole).translation;
    let world_p_base = data.p_base_world;
    let chain: Vec<usize> = model.support(model.frames[sole].body).collect();
    let mut length = 0.0;
    let mut below = world_p_sole;
    for &body in &chain {
        let origin = world_p_base + data.p_body_rel[body];
        length += (origin - below).norm();
        below = origin;
    }
    (length, below.z - world_p_sole.z)
}

/// The longest step the legs reach from the stance `q`: with the CoM midway between the
/// feet each sole is half the step from under its hip, so `2 sqrt(L^2 - h^2)` with the
/// straight leg `L` and the hip height `h` ([`leg_length_and_hip_height`]), the shorter leg's.
pub fn legs_reach(model: &Model, q: &[f64], soles: &[FrameId]) -> f64 {
    soles
        .iter()
        .map(|&sole| {
            let (length, height) = leg_length_and_hip_height(model, q, sole);
            2.0 * (length * length - height * height).max(0.0).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// With `[walking]`: checks `walking.max_step_length` against the legs' reach at `q` and
/// makes `controller` walk the gait from `q` (its errors name the key).
pub fn set_up(
    scenario: &Scenario,
    model: &Model,
    soles: &[FrameId],
    q: &[f64],
    controller: &mut MomentumController,
) -> Result<()> {
    let Some(walking) = &scenario.walking else {
        return Ok(());
    };
    let reach = legs_reach(model, q, soles);
    if walking.max_step_length > reach {
        return Err(Error::invalid(
            "walking.max_step_length",
            format!(
                "must be at most the legs' reach from the initial posture, {reach:.3} m \
                 (2 sqrt(L^2 - h^2): straight leg L, hip height h)"
            ),
            walking.max_step_length,
        ));
    }
    controller.set_walking(walking, q, scenario.schedule().period)?;
    Ok(())
}
