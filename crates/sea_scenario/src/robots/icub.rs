//! The iCub of the paper and of the original MATLAB study: its robot description is the file
//! `robots/icub_paper.toml` of the repository (its 25 joints, initial postures, contact frames,
//! joint groups, postural stiffness by joint group, momentum gains and the study's settings of
//! the plant and the controller), embedded in the binary: the one place these figures are
//! written.

use super::RobotDescription;
use std::sync::LazyLock;

/// Name of the built-in description (`[robot] description = "icub_paper"`, the default).
pub const ICUB_PAPER: &str = "icub_paper";

/// The text of `robots/icub_paper.toml`.
pub const ICUB_PAPER_TOML: &str = include_str!("../../../../robots/icub_paper.toml");

/// The iCub, read once.
static ICUB: LazyLock<RobotDescription> = LazyLock::new(|| {
    // The file is part of the binary and read by a test: it cannot fail at run time.
    RobotDescription::from_toml(ICUB_PAPER_TOML, ICUB_PAPER)
        .unwrap_or_else(|e| unreachable!("robots/icub_paper.toml: {e}"))
});

/// The paper's iCub.
pub fn icub() -> &'static RobotDescription {
    &ICUB
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Owned names.
    fn names(names: &[&str]) -> Vec<String> {
        names.iter().map(|name| name.to_string()).collect()
    }

    #[test]
    fn the_embedded_file_reads_and_holds_the_papers_25_joints() {
        let robot = RobotDescription::from_toml(ICUB_PAPER_TOML, ICUB_PAPER).unwrap();
        assert_eq!(robot.joints.len(), 25);
        assert_eq!(robot.joints[0], "torso_pitch");
        assert_eq!(robot.joints[24], "r_ankle_roll");
        assert_eq!(robot.contacts, names(&["l_sole"]));
        assert_eq!(robot.initial_posture, "left_stance");
        assert_eq!(robot.postures["left_stance"].angles[22], -1.7688);
        assert_eq!(
            robot.postures["two_feet"].radians()[0],
            (-10.0f64).to_radians()
        );
        assert_eq!(
            robot.momentum_integral.two_feet,
            [40.0, 45.0, 40.0, 1.0, 5.0, 1.0]
        );
        assert_eq!(
            (robot.postural_scale, robot.motor_velocity_gain),
            (0.2, 200.0)
        );
        assert_eq!(
            (
                robot.joint_inertia_regularization,
                robot.pinv_damping,
                robot.qp_regularization
            ),
            (0.1, 5e-4, 1e-3)
        );
        assert!(robot.urdf.is_none() && robot.foot.is_none() && robot.actuator.is_none());
    }

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
        let joints = icub().joints.clone();
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
        let read = RobotDescription::from_toml(&text, "round trip").unwrap();
        assert_eq!(&read, icub());
    }

    #[test]
    fn a_posture_of_the_wrong_length_is_refused_naming_it() {
        let text = ICUB_PAPER_TOML.replace("-1.7688, 0.4568, -0.0163,", "-1.7688,");
        let message = RobotDescription::from_toml(&text, "x.toml")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("x.toml: postures.left_stance.angles"),
            "{message}"
        );
    }
}
