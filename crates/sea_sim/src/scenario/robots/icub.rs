//! The iCub of the paper and of the original MATLAB study: its 25 joints, initial postures,
//! contact frames, joint groups, postural stiffness by joint group, momentum gains and the
//! study's settings of the plant and the controller. The one place these figures are written.

use super::{
    AngleUnit, JointSelector, MomentumIntegral, PosturalStiffness, Posture, RobotDescription,
};
use std::collections::BTreeMap;
use std::sync::LazyLock;

/// The 25 iCub joints of the paper, in the original study's order.
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
const LEFT_STANCE_RAD: [f64; 25] = [
    0.0462, -0.5256, -0.0269, 0.1874, 1.6258, 0.2462, 0.3053, -0.0948, -0.3553, 1.8546, 0.7323,
    0.3905, -0.1169, 0.1047, 0.2547, 0.0378, 0.0732, 0.0958, 0.1637, 0.2923, 0.8611, 1.2866,
    -1.7688, 0.4568, -0.0163,
];

/// Two-feet initial joints of the original study [deg], order of [`ICUB25_JOINTS`].
const TWO_FEET_DEG: [f64; 25] = [
    -10.0, 0.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, 25.5, 0.0, 0.0,
    -18.5, -5.5, 0.0, 25.5, 0.0, 0.0, -18.5, -5.5, 0.0,
];

/// Arm joints: names containing one of these.
const ARM_PARTS: [&str; 3] = ["shoulder", "elbow", "wrist"];

/// The iCub, built once.
static ICUB: LazyLock<RobotDescription> = LazyLock::new(describe_icub);

/// The paper's iCub.
pub fn icub() -> &'static RobotDescription {
    &ICUB
}

/// Owned names.
fn names(names: &[&str]) -> Vec<String> {
    names.iter().map(|name| name.to_string()).collect()
}

/// The original study's postures: one foot (left stance, radians) and two feet (degrees).
fn postures() -> BTreeMap<String, Posture> {
    BTreeMap::from([
        (
            "left_stance".to_string(),
            Posture {
                unit: AngleUnit::Rad,
                angles: LEFT_STANCE_RAD.to_vec(),
            },
        ),
        (
            "two_feet".to_string(),
            Posture {
                unit: AngleUnit::Deg,
                angles: TWO_FEET_DEG.to_vec(),
            },
        ),
    ])
}

/// `torso`, `left_arm`, `right_arm`, `arms` (left then right) and `upper_body` (torso, left
/// arm, right arm).
fn joint_groups() -> BTreeMap<String, Vec<JointSelector>> {
    let select = |prefix: &str, contains: &[&str]| JointSelector {
        prefix: prefix.into(),
        contains: names(contains),
    };
    let (torso, left, right) = (
        select("torso", &[]),
        select("l_", &ARM_PARTS),
        select("r_", &ARM_PARTS),
    );
    BTreeMap::from([
        ("torso".into(), vec![torso.clone()]),
        ("left_arm".into(), vec![left.clone()]),
        ("right_arm".into(), vec![right.clone()]),
        ("arms".into(), vec![left.clone(), right.clone()]),
        ("upper_body".into(), vec![torso, left, right]),
    ])
}

/// The original study's postural stiffness (one foot): torso [10 15 10], each arm
/// [5 5 5 2.5 2.5], the stance leg [15 15 15 15 5 5], a swing leg [10 10 15 15 5 5]; any other
/// joint 5.
fn postural_stiffness() -> PosturalStiffness {
    PosturalStiffness {
        sides: names(&["l", "r"]),
        leg_joints: names(&[
            "hip_pitch",
            "hip_roll",
            "hip_yaw",
            "knee",
            "ankle_pitch",
            "ankle_roll",
        ]),
        stance_leg: vec![15.0, 15.0, 15.0, 15.0, 5.0, 5.0],
        swing_leg: vec![10.0, 10.0, 15.0, 15.0, 5.0, 5.0],
        by_name: BTreeMap::from([
            ("torso_pitch".into(), 10.0),
            ("torso_yaw".into(), 10.0),
            ("torso_roll".into(), 15.0),
        ]),
        by_suffix: vec![("elbow".into(), 2.5), ("wrist_prosup".into(), 2.5)],
        other: 5.0,
    }
}

/// The iCub of the paper and the original study. Momentum integral gains: one foot CoM
/// diag(6, 7, 6) and angular diag(0.5, 1, 0.5); two feet diag(40, 45, 40) and diag(1, 5, 1)
/// (the proportional gains default to their critical damping). The study divides the
/// postural stiffness by 5, adds 0.1 kg m^2 to the joint block of `M` in plant and controller
/// (without it the light wrists turn tiny torque errors into large accelerations), closes the
/// motor velocity loop at 200 1/s, damps the pseudo-inverse of `Lambda` by 5e-4 and
/// regularises the QP Hessian by 1e-3.
fn describe_icub() -> RobotDescription {
    RobotDescription {
        joints: names(&ICUB25_JOINTS),
        postures: postures(),
        contacts: names(&["l_sole"]),
        joint_groups: joint_groups(),
        postural_stiffness: postural_stiffness(),
        postural_scale: 0.2,
        momentum_integral: MomentumIntegral {
            one_foot: [6.0, 7.0, 6.0, 0.5, 1.0, 0.5],
            two_feet: [40.0, 45.0, 40.0, 1.0, 5.0, 1.0],
        },
        motor_velocity_gain: 200.0,
        joint_inertia_regularization: 0.1,
        pinv_damping: 5e-4,
        qp_regularization: 1e-3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn postural_stiffness_follows_the_stance_leg() {
        let left = vec!["l_sole".to_string()];
        let stiffness = |name: &str| icub().postural_stiffness.of(name, &left);
        assert_eq!(stiffness("l_hip_pitch"), 15.0);
        assert_eq!(stiffness("r_hip_pitch"), 10.0);
        assert_eq!(stiffness("r_ankle_roll"), 5.0);
        assert_eq!(stiffness("torso_roll"), 15.0);
        assert_eq!(stiffness("torso_pitch"), 10.0);
        assert_eq!(stiffness("l_wrist_prosup"), 2.5);
        assert_eq!(stiffness("r_elbow"), 2.5);
        assert_eq!(stiffness("l_shoulder_yaw"), 5.0);
        assert_eq!(stiffness("neck_pitch"), 5.0);
    }

    #[test]
    fn every_posture_has_one_angle_per_joint() {
        for (name, posture) in &icub().postures {
            assert_eq!(posture.angles.len(), icub().joints.len(), "{name}");
        }
    }

    #[test]
    fn groups_pick_joints_in_model_order() {
        let joints = names(&ICUB25_JOINTS);
        let arms = icub().group("arms", &joints).unwrap();
        assert_eq!(arms.len(), 10);
        assert_eq!(
            (arms[0].as_str(), arms[5].as_str()),
            ("l_shoulder_pitch", "r_shoulder_pitch")
        );
        assert_eq!(icub().group("upper_body", &joints).unwrap().len(), 13);
        assert_eq!(icub().group("legs", &joints), None);
    }

    #[test]
    fn the_description_reads_back_from_toml() {
        let text = toml::to_string(icub()).unwrap();
        let read: RobotDescription = toml::from_str(&text).unwrap();
        assert_eq!(&read, icub());
    }
}
