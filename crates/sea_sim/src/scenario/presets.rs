//! The iCub of the paper and of the original study (docs/references.md): its 25 joints, initial
//! postures, contact frames, postural stiffness by joint group, momentum gains and the
//! study's settings of the plant and the controller. The one place these figures are written:
//! the scenario schema's defaults, the scenario builder and the Python bindings read them here.

/// The 25 iCub joints of the paper, in the original study's order
/// (docs/references.md#original-study-joints-and-contacts).
pub const ICUB25_JOINTS: [&str; 25] = [
    "torso_pitch",
    "torso_roll",
    "torso_yaw",
    "l_shoulder_pitch",
    "l_shoulder_roll",
    "l_shoulder_yaw",
    "l_elbow",
    "l_wrist_prosup",
    "r_shoulder_pitch",
    "r_shoulder_roll",
    "r_shoulder_yaw",
    "r_elbow",
    "r_wrist_prosup",
    "l_hip_pitch",
    "l_hip_roll",
    "l_hip_yaw",
    "l_knee",
    "l_ankle_pitch",
    "l_ankle_roll",
    "r_hip_pitch",
    "r_hip_roll",
    "r_hip_yaw",
    "r_knee",
    "r_ankle_pitch",
    "r_ankle_roll",
];

/// Left-foot stance initial joints of the original study [rad], order of [`ICUB25_JOINTS`].
pub const ICUB_LEFT_STANCE: [f64; 25] = [
    0.0462, -0.5256, -0.0269, 0.1874, 1.6258, 0.2462, 0.3053, -0.0948, -0.3553, 1.8546, 0.7323,
    0.3905, -0.1169, 0.1047, 0.2547, 0.0378, 0.0732, 0.0958, 0.1637, 0.2923, 0.8611, 1.2866,
    -1.7688, 0.4568, -0.0163,
];

/// Two-feet initial joints of the original study [deg], order of [`ICUB25_JOINTS`].
pub const ICUB_TWO_FEET_DEG: [f64; 25] = [
    -10.0, 0.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, 25.5, 0.0, 0.0,
    -18.5, -5.5, 0.0, 25.5, 0.0, 0.0, -18.5, -5.5, 0.0,
];

/// Contact frames of the one-foot demos: the left sole is the stance foot
/// (docs/references.md#original-study-joints-and-contacts).
pub const ICUB_STANCE_CONTACTS: [&str; 1] = ["l_sole"];

/// Motor velocity loop gain `K_m` [1/s] of the original study
/// (docs/references.md#original-study-sea-parameters).
pub const ICUB_MOTOR_VELOCITY_GAIN: f64 = 200.0;

/// Added to the joint block of `M` [kg m^2] in plant and controller by the original study
/// (docs/references.md#original-study-plant); without it the light wrists turn tiny torque
/// errors into large accelerations.
pub const ICUB_JOINT_INERTIA_REGULARIZATION: f64 = 0.1;

/// The original study divides the postural stiffness of [`icub_postural_stiffness`] by 5
/// (docs/references.md#original-study-postural-task).
pub const ICUB_POSTURAL_SCALE: f64 = 0.2;

/// Damping of the pseudo-inverse of `Lambda` in the original study
/// (docs/references.md#original-study-contact-wrench-qp).
pub const ICUB_PINV_DAMPING: f64 = 5e-4;

/// QP Hessian regulariser of the original study
/// (docs/references.md#original-study-contact-wrench-qp).
pub const ICUB_QP_REGULARIZATION: f64 = 1e-3;

/// Momentum integral gains `K_i` of the original study
/// (docs/references.md#original-study-momentum-gains),
/// linear xyz then angular xyz: one foot integral CoM diag(6, 7, 6) and angular
/// diag(0.5, 1, 0.5); two feet diag(40, 45, 40) and diag(1, 5, 1). The proportional gains
/// default to their critical damping ([`sea_dyn::critical_damping`]).
pub fn icub_momentum_integral(one_foot: bool) -> [f64; 6] {
    if one_foot {
        [6.0, 7.0, 6.0, 0.5, 1.0, 0.5]
    } else {
        [40.0, 45.0, 40.0, 1.0, 5.0, 1.0]
    }
}

/// Postural stiffness of joint `name` by group, before [`ICUB_POSTURAL_SCALE`] (one foot,
/// docs/references.md#original-study-postural-task): torso [10 15 10], each arm
/// [5 5 5 2.5 2.5], a leg whose sole is in `contacts` [15 15 15 15 5 5], a swing leg
/// [10 10 15 15 5 5]; any other joint 5.
pub fn icub_postural_stiffness(name: &str, contacts: &[String]) -> f64 {
    const LEG: [&str; 6] = [
        "hip_pitch",
        "hip_roll",
        "hip_yaw",
        "knee",
        "ankle_pitch",
        "ankle_roll",
    ];
    const STANCE_LEG: [f64; 6] = [15.0, 15.0, 15.0, 15.0, 5.0, 5.0];
    const SWING_LEG: [f64; 6] = [10.0, 10.0, 15.0, 15.0, 5.0, 5.0];
    for side in ["l", "r"] {
        let leg_index = name
            .strip_prefix(side)
            .and_then(|rest| rest.strip_prefix('_'))
            .and_then(|joint| LEG.iter().position(|j| *j == joint));
        if let Some(k) = leg_index {
            let stance = contacts.iter().any(|c| c.starts_with(side));
            return if stance { STANCE_LEG[k] } else { SWING_LEG[k] };
        }
    }
    match name {
        "torso_pitch" | "torso_yaw" => 10.0,
        "torso_roll" => 15.0,
        n if n.ends_with("elbow") || n.ends_with("wrist_prosup") => 2.5,
        _ => 5.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn postural_stiffness_follows_the_stance_leg() {
        let left = vec!["l_sole".to_string()];
        assert_eq!(icub_postural_stiffness("l_hip_pitch", &left), 15.0);
        assert_eq!(icub_postural_stiffness("r_hip_pitch", &left), 10.0);
        assert_eq!(icub_postural_stiffness("r_ankle_roll", &left), 5.0);
        assert_eq!(icub_postural_stiffness("torso_roll", &left), 15.0);
        assert_eq!(icub_postural_stiffness("l_wrist_prosup", &left), 2.5);
        assert_eq!(icub_postural_stiffness("l_shoulder_yaw", &left), 5.0);
    }
}
