//! `[walking]` on a built scenario: the legs' reach checked against the step length, and the
//! controller set to walk (`sea_ctrl::MomentumController::set_walking`).

use crate::error::{Error, Result};
use crate::Scenario;
use sea_ctrl::controller::MomentumController;
use sea_ctrl::walking::{RobotWalkingFigures, WalkingSettings};
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

/// The figures of the robot standing at `q` on `soles` that the walking settings scale with:
/// the CoM's height above the soles, the soles' horizontal distance, the shorter straight leg
/// ([`leg_length_and_hip_height`]) and the legs' reach ([`legs_reach`]).
pub fn walking_figures(model: &Model, q: &[f64], soles: &[FrameId]) -> RobotWalkingFigures {
    let mut data = Data::new(model);
    let world_p_com = sea_dyn::centroidal::com(model, &mut data, q);
    sea_dyn::forward_kinematics(model, &mut data, q);
    let placements: Vec<_> = soles
        .iter()
        .map(|&sole| sea_dyn::frame_placement(model, &data, sole).translation)
        .collect();
    let count = placements.len().max(1) as f64;
    let world_z_soles = placements.iter().map(|p| p.z).sum::<f64>() / count;
    let feet_distance = match placements[..] {
        [left, right] => (left - right).xy().norm(),
        _ => 0.0,
    };
    let leg_length = soles
        .iter()
        .map(|&sole| leg_length_and_hip_height(model, q, sole).0)
        .fold(f64::INFINITY, f64::min);
    RobotWalkingFigures {
        com_height: world_p_com.z - world_z_soles,
        feet_distance,
        leg_length,
        reach: legs_reach(model, q, soles),
    }
}

/// The walking settings of `scenario` for the robot standing at `q` on `soles`: `[walking]`
/// as read, or, when its robot description is not the paper's iCub
/// ([`Scenario::walking_given`]), the keys it gives over the defaults scaled to the robot
/// (`WalkingSettings::scaled_to` of [`walking_figures`]; docs/explanation/walking.md#settings).
/// `None` without `[walking]`.
pub fn walking_settings(
    scenario: &Scenario,
    model: &Model,
    q: &[f64],
    soles: &[FrameId],
) -> Result<Option<WalkingSettings>> {
    let Some(walking) = &scenario.walking else {
        return Ok(None);
    };
    let Some(given) = &scenario.walking_given else {
        return Ok(Some(walking.clone()));
    };
    let scaled = WalkingSettings::scaled_to(&walking_figures(model, q, soles))?;
    let mut table =
        toml::Table::try_from(&scaled).map_err(|e| Error::config("walking", e.to_string()))?;
    for (key, value) in given {
        table.insert(key.clone(), value.clone());
    }
    let settings = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| Error::config("walking", e.to_string()))?;
    Ok(Some(settings))
}

/// With `[walking]`: checks `walking.max_step_length` of [`walking_settings`] against the
/// legs' reach at `q` and makes `controller` walk the gait from `q` (its errors name the key).
/// Returns the warnings: the command's axes the step limits clip (`sea_ctrl`'s
/// `command_clips`), the walk then slower than commanded.
pub fn set_up(
    scenario: &Scenario,
    model: &Model,
    soles: &[FrameId],
    q: &[f64],
    controller: &mut MomentumController,
) -> Result<Vec<String>> {
    let Some(walking) = walking_settings(scenario, model, q, soles)? else {
        return Ok(Vec::new());
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
    controller.set_walking(&walking, q, scenario.schedule().period)?;
    let clips = sea_ctrl::walking::command_clips(&walking);
    Ok(clips.iter().map(ToString::to_string).collect())
}
