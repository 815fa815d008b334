//! `sea-sim init` (sea_sim::init): a scenario for a robot it has never seen, and bad input
//! refused with an error naming the element, nothing written.

use sea_sim::init::{init, parse_foot, InitOptions};
use sea_sim::scenario::robots::FootRectangle;
use sea_sim::scenario::{build, Scenario};
use std::path::{Path, PathBuf};

/// The paper's iCub URDF of the repository.
fn icub_urdf() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../urdf/icub25.urdf")
        .display()
        .to_string()
}

/// A fresh folder for one test's output.
fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sea_sim_init_{test}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Options for the iCub on its two soles, writing into `dir`.
fn icub_options(dir: &Path) -> InitOptions {
    InitOptions {
        urdf: icub_urdf(),
        contacts: ["l_sole".into(), "r_sole".into()],
        foot: Some(FootRectangle {
            x: [-0.05, 0.10],
            y: [-0.025, 0.025],
        }),
        out: dir.join("icub_two_feet.toml"),
        ..Default::default()
    }
}

/// Options for the mini biped (legs of five joints) on its soles with `foot`, writing into
/// `dir`.
fn mini_biped_options(dir: &Path, foot: FootRectangle) -> InitOptions {
    InitOptions {
        urdf: Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../urdf/mini_biped.urdf")
            .display()
            .to_string(),
        foot: Some(foot),
        ..icub_options(dir)
    }
}

/// The error message of `options` and whether the output file was left absent.
fn refused(options: &InitOptions) -> String {
    let message = init(options).unwrap_err().to_string();
    assert!(!options.out.exists(), "{message}: the file was written");
    let dir = options.out.parent().unwrap();
    let left: Vec<_> = std::fs::read_dir(dir).unwrap().collect();
    assert!(left.is_empty(), "{message}: {left:?} left behind");
    message
}

#[test]
fn the_written_scenario_builds_with_both_soles_flat_on_the_ground() {
    let dir = folder("icub");
    let options = icub_options(&dir);
    let report = init(&options).unwrap();
    assert!(report.residual < 1e-6, "{}", report.residual);
    // Legs of 6 joints: the paper's full-rank contact set, the paper's QP.
    assert_eq!(report.feet_rank, 12);
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    assert_eq!(scenario.robot.contacts, ["l_sole", "r_sole"]);
    let setup = build(&scenario).unwrap();
    assert!(!setup.controller.redundant_contacts());
    let mut data = sea_dyn::Data::new(&setup.model);
    let q = &setup.x0[..setup.model.nq()];
    sea_dyn::forward_kinematics(&setup.model, &mut data, q);
    for name in ["l_sole", "r_sole"] {
        let frame = setup.model.frame_id(name).unwrap();
        let sole = sea_dyn::frame_placement(&setup.model, &data, frame);
        assert!(
            sole.translation.z.abs() < 1e-6,
            "{name}: {}",
            sole.translation
        );
        assert!(
            (sole.rotation[(2, 2)] - 1.0).abs() < 1e-9,
            "{name} not flat"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_contact_link_that_does_not_exist_is_named() {
    let dir = folder("unknown_link");
    for contact in ["l_sloe", "l_foot_link:0,0,0"] {
        let mut options = icub_options(&dir);
        options.contacts[0] = contact.into();
        let message = refused(&options);
        let link = contact.split(':').next().unwrap();
        assert!(
            message.contains("robot.contacts") && message.contains(&format!("'{link}'")),
            "{message}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_foot_rectangle_with_x0_not_below_x1_is_refused() {
    let message = parse_foot("0.1,0.1,-0.05,0.05").unwrap_err().to_string();
    assert!(
        message.contains("foot") && message.contains("x0 < x1"),
        "{message}"
    );
    let message = parse_foot("0.1,x,-0.05,0.05").unwrap_err().to_string();
    assert!(message.contains("four finite numbers"), "{message}");
    let dir = folder("foot");
    let mut options = icub_options(&dir);
    options.foot = Some(FootRectangle {
        x: [0.1, -0.05],
        y: [-0.025, 0.025],
    });
    let message = refused(&options);
    assert!(message.contains("x0 = 0.1, x1 = -0.05"), "{message}");
    options.foot = Some(FootRectangle {
        x: [-1e300, 1e300],
        y: [-0.025, 0.025],
    });
    let message = refused(&options);
    assert!(
        message.contains("foot") && message.contains("within 1 m"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_scenario_written_over_its_own_urdf_is_refused_and_the_urdf_kept() {
    let dir = folder("over_urdf");
    let urdf = dir.join("robot.urdf");
    std::fs::copy(icub_urdf(), &urdf).unwrap();
    refused_over(
        &dir,
        &urdf,
        &urdf,
        "the scenario written would overwrite the URDF",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// A robot with one leg ending in two toes.
const ONE_LEG: &str = r#"<robot name="one_leg">
  <link name="base"><inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="thigh"><inertial><origin xyz="0 0 -0.2"/><mass value="2"/><inertia ixx="0.02" iyy="0.02" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="shin"><inertial><origin xyz="0 0 -0.2"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="toe_a"/><link name="toe_b"/>
  <joint name="hip" type="revolute"><parent link="base"/><child link="thigh"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shin"/><origin xyz="0 0 -0.4"/><axis xyz="0 1 0"/><limit lower="0" upper="2" effort="10" velocity="1"/></joint>
  <joint name="toe_a_fix" type="fixed"><parent link="shin"/><child link="toe_a"/><origin xyz="0.05 0.05 -0.4"/></joint>
  <joint name="toe_b_fix" type="fixed"><parent link="shin"/><child link="toe_b"/><origin xyz="0.05 -0.05 -0.4"/></joint>
</robot>"#;

#[test]
fn a_robot_that_cannot_stand_is_refused() {
    let dir = folder("one_leg");
    let urdf_dir = folder("one_leg_urdf");
    let urdf = urdf_dir.join("one_leg.urdf");
    std::fs::write(&urdf, ONE_LEG).unwrap();
    let mut options = icub_options(&dir);
    options.urdf = urdf.display().to_string();
    options.contacts = ["toe_a".into(), "toe_b".into()];
    let message = refused(&options);
    assert!(
        message.contains("cannot stand") && message.contains("'toe_a', 'toe_b'"),
        "{message}"
    );
    let mut same_leg = icub_options(&dir);
    same_leg.contacts = ["l_sole".into(), "l_ankle_2".into()];
    let message = refused(&same_leg);
    assert!(message.contains("cannot stand"), "{message}");
    std::fs::remove_dir_all(dir).unwrap();
    std::fs::remove_dir_all(urdf_dir).unwrap();
}

/// A joint whose inertia standing is negative (it moves the mini biped's torso, given
/// principal moments of -1 kg m^2) is refused naming it: its postural gain would be
/// negative, and the scenario written would not run.
#[test]
fn a_joint_whose_inertia_is_negative_is_refused_naming_it() {
    let dir = folder("negative_inertia");
    let urdf_dir = folder("negative_inertia_urdf");
    let urdf = urdf_dir.join("negative.urdf");
    let foot = FootRectangle {
        x: [-0.05, 0.08],
        y: [-0.03, 0.03],
    };
    let text = std::fs::read_to_string(mini_biped_options(&dir, foot).urdf).unwrap();
    let torso = r#"ixx="0.0213542" ixy="0" ixz="-0.0008" iyy="0.0160208" iyz="0" izz="0.0113333""#;
    assert!(text.contains(torso), "the torso's inertia");
    let negative = r#"ixx="-1" ixy="0" ixz="-0.0008" iyy="-1" iyz="0" izz="-1""#;
    std::fs::write(&urdf, text.replace(torso, negative)).unwrap();
    let mut options = mini_biped_options(&dir, foot);
    options.urdf = urdf.display().to_string();
    let message = refused(&options);
    assert!(
        message.contains("joint 'torso_pitch'") && message.contains("negative principal inertia"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
    std::fs::remove_dir_all(urdf_dir).unwrap();
}

/// The mini biped's legs have 5 joints (no hip yaw): its two feet's 12 constraints have rank
/// 11 and the controller's `Lambda` rank 10 (a redundant contact set). `init` writes its
/// scenario (with the larger pseudo-inverse damping) and the written scenario, unedited,
/// balances: the run completes its 5 s with the controller's redundant-contact QP, no QP
/// failure, the CoM within a tenth of a millimetre of its sinusoid (measured: rms 29 um, max
/// 48 um) and the joints within 0.1 rad of the standing posture (measured 0.013 rad).
#[test]
fn two_feet_on_legs_of_five_joints_are_written_and_balance() {
    let dir = folder("mini_biped");
    let foot = FootRectangle {
        x: [-0.05, 0.08],
        y: [-0.03, 0.03],
    };
    let options = mini_biped_options(&dir, foot);
    let report = init(&options).unwrap();
    assert_eq!(report.feet_rank, 11);
    assert_eq!(report.com_offset_m, 0.0);
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    assert_eq!(
        scenario.controller.tuning.pinv_damping,
        sea_sim::init::write::REDUNDANT_PINV_DAMPING
    );
    let setup = build(&scenario).unwrap();
    assert!(setup.controller.redundant_contacts());
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let summary =
        sea_sim::closed_loop::run_with_sinks(&scenario, &mut [], &cancel, |_, _| {}).unwrap();
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.duration_s, 5.0);
    assert_eq!(summary.qp_failures, 0);
    assert!(
        summary.com_error_rms_m < 1e-4,
        "{}",
        summary.com_error_rms_m
    );
    assert!(
        summary.joint_error_norm_final_rad < 0.1,
        "{}",
        summary.joint_error_norm_final_rad
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// A foot rectangle off-centre sideways asks the CoM to shift sideways, which legs of five
/// joints bent at the hips cannot do with both soles flat and the base upright (a hip roll
/// yaws the foot): `init` stands the CoM above the rectangles' centres along the feet instead,
/// says how far that is (5 mm here), and the scenario balances. It was refused from 4 um off.
#[test]
fn a_foot_off_centre_sideways_on_legs_of_five_joints_stands_the_com_along_the_feet() {
    let dir = folder("mini_biped_off_centre");
    let foot = FootRectangle {
        x: [-0.05, 0.05],
        y: [-0.03, 0.04],
    };
    let options = mini_biped_options(&dir, foot);
    let report = init(&options).unwrap();
    assert!(
        (report.com_offset_m - 0.005).abs() < 1e-9,
        "{}",
        report.com_offset_m
    );
    let one_second = [("simulation.duration_s".to_string(), "1".to_string())];
    let scenario = Scenario::from_file(&options.out, &one_second).unwrap();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let summary =
        sea_sim::closed_loop::run_with_sinks(&scenario, &mut [], &cancel, |_, _| {}).unwrap();
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.qp_failures, 0);
    std::fs::remove_dir_all(dir).unwrap();
}

/// The standing angles `init` wrote into the scenario file `path`.
fn written_standing_angles(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let root: toml::Table = toml::from_str(&text).unwrap();
    let angles = &root["robot"]["description"]["postures"]["standing"]["angles"];
    let angles = angles.as_array().unwrap().iter();
    angles.map(|a| a.as_float().unwrap()).collect()
}

/// The mini biped's redundant contacts at postures a round-off apart: the four roll angles
/// `init` writes as round-off (about 1e-18 rad) set to 0 or +-1e-18 in all 81 ways. The
/// consistency row of its QP comes from the leading singular direction of a wide, nearly
/// rank-one matrix; nalgebra's SVD of it was wrong at 36 of these postures (the QP infeasible
/// from the first tick, the run diverged at 0.06 s); each now balances.
#[test]
fn the_redundant_contacts_hold_at_postures_a_round_off_apart() {
    let dir = folder("mini_biped_round_off");
    let foot = FootRectangle {
        x: [-0.05, 0.05],
        y: [-0.03, 0.03],
    };
    let options = mini_biped_options(&dir, foot);
    init(&options).unwrap();
    let written = written_standing_angles(&options.out);
    let round_off: Vec<usize> = (0..written.len())
        .filter(|&i| written[i].abs() < 1e-12)
        .collect();
    assert!(round_off.len() >= 4, "{written:?}");
    let cancel = std::sync::atomic::AtomicBool::new(false);
    for case in 0..81 {
        let mut angles = written.clone();
        for (digit, &i) in round_off.iter().rev().take(4).enumerate() {
            angles[i] = [0.0, 1e-18, -1e-18][case / 3usize.pow(digit as u32) % 3];
        }
        let listed: Vec<String> = angles.iter().map(|a| format!("{a:e}")).collect();
        let overrides = [
            (
                "robot.description.postures.standing.angles".to_string(),
                format!("[{}]", listed.join(", ")),
            ),
            ("simulation.duration_s".to_string(), "0.3".to_string()),
        ];
        let scenario = Scenario::from_file(&options.out, &overrides).unwrap();
        let summary =
            sea_sim::closed_loop::run_with_sinks(&scenario, &mut [], &cancel, |_, _| {}).unwrap();
        assert_eq!(
            summary.status, "completed",
            "{angles:?}: {}",
            summary.reason
        );
        assert_eq!(summary.qp_failures, 0, "{angles:?}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_unresolvable_package_uri_is_named() {
    let dir = folder("package");
    let mut options = icub_options(&dir);
    options.urdf = "package://no_such_package_xyz/robots/robot.urdf".into();
    let message = refused(&options);
    assert!(
        message.contains("urdf") && message.contains("no_such_package_xyz"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_link_point_with_a_bad_number_is_named() {
    let dir = folder("bad_number");
    let mut options = icub_options(&dir);
    options.contacts[1] = "r_ankle_2:0,0,-0.0x3".into();
    let message = refused(&options);
    assert!(
        message.contains("robot.contacts") && message.contains("'-0.0x3' is not a finite number"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// A mesh the URDF names but that is not there (a missing file, an unknown package) stops the
/// setup before anything is written, naming the link and the URI.
#[test]
fn a_missing_or_unresolvable_mesh_is_named() {
    for (uri, why) in [
        ("meshes/no_such_part.stl", "no_such_part.stl"),
        ("package://no_such_pkg_xyz/part.stl", "no_such_pkg_xyz"),
    ] {
        let dir = folder("mesh");
        let urdf_dir = folder("mesh_urdf");
        let urdf = urdf_dir.join("icub_mesh.urdf");
        write_icub_with_chest_mesh(&urdf, uri);
        let mut options = icub_options(&dir);
        options.urdf = urdf.display().to_string();
        let message = refused(&options);
        assert!(
            message.contains("link 'chest' visual mesh") && message.contains(why),
            "{message}"
        );
        std::fs::remove_dir_all(dir).unwrap();
        std::fs::remove_dir_all(urdf_dir).unwrap();
    }
}

/// The scenario written must not replace a mesh the URDF names (it used to overwrite a foot's
/// collision mesh given as `--out`, and the next `init` could not read the foot).
#[test]
fn a_scenario_written_over_a_mesh_of_the_urdf_is_refused_and_the_mesh_kept() {
    let dir = folder("over_mesh");
    let urdf = dir.join("icub_mesh.urdf");
    write_icub_with_chest_mesh(&urdf, "part.stl");
    let mesh = dir.join("part.stl");
    std::fs::write(&mesh, "solid part\nendsolid part\n").unwrap();
    refused_over(
        &dir,
        &urdf,
        &mesh,
        "would overwrite the link 'chest' visual mesh",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Writes at `urdf` the iCub's URDF with one more visual mesh on the chest, `uri`, beside the
/// chest's own visuals (urdf-rs wants a link's visuals together).
fn write_icub_with_chest_mesh(urdf: &Path, uri: &str) {
    let text = std::fs::read_to_string(icub_urdf()).unwrap();
    let chest = text.find("<link name=\"chest\">").expect("the chest link");
    let at = chest
        + text[chest..]
            .find("<visual")
            .expect("a visual of the chest");
    let visual = format!("<visual><geometry><mesh filename=\"{uri}\"/></geometry></visual>");
    std::fs::write(urdf, format!("{}{visual}{}", &text[..at], &text[at..])).unwrap();
}

/// `init` of the iCub options in `dir` with the URDF `urdf`, asked to write over `target`: the
/// error says `expected` and `target` keeps its bytes.
fn refused_over(dir: &Path, urdf: &Path, target: &Path, expected: &str) {
    let before = std::fs::read(target).unwrap();
    let mut options = icub_options(dir);
    options.urdf = urdf.display().to_string();
    options.out = target.to_path_buf();
    let message = init(&options).unwrap_err().to_string();
    assert!(message.contains(expected), "{message}");
    assert_eq!(std::fs::read(target).unwrap(), before);
}

/// Runs a walk `init` wrote: it completes, its 8 steps and the stop taken.
fn walks_its_eight_steps_and_the_stop(scenario: &Scenario) {
    let (_, summary) = sea_sim::scenario::run::run(scenario, |_, _| ()).unwrap();
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.steps_taken, Some(9));
}

/// `init --walking` for the iCub: the `[walking]` written is the scaled rule's
/// (`WalkingSettings::scaled_to` of the figures `init` reports, rounded to 1 mm and 1 ms; the
/// iCub's own legs give `k` = 1, so the durations are the defaults'), the scenario builds, and
/// the robot walks its 8 steps and the stop without a fall.
#[test]
fn a_walking_scenario_is_written_scaled_to_the_robot_and_walks() {
    use sea_ctrl::walking::WalkingSettings;
    let dir = folder("icub_walk");
    let options = InitOptions {
        walking: true,
        out: dir.join("icub_walk.toml"),
        ..icub_options(&dir)
    };
    let report = init(&options).unwrap();
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    let written = scenario.walking.clone().expect("[walking]");
    let scaled = WalkingSettings::scaled_to(&report.walking_figures).unwrap();
    let figures = report.walking_figures;
    assert!((figures.leg_length - sea_ctrl::walking::ICUB_LEG_LENGTH).abs() < 1e-4);
    for (written, rule) in [
        (written.com_height, scaled.com_height),
        (written.nominal_width, scaled.nominal_width),
        (written.max_step_length, scaled.max_step_length),
        (written.swing_height, scaled.swing_height),
        (written.step_duration, scaled.step_duration),
        (written.transfer_duration, scaled.transfer_duration),
    ] {
        assert!((written - rule).abs() <= 5e-4, "{written} against {rule}");
    }
    assert!((written.step_duration - WalkingSettings::default().step_duration).abs() < 1e-3);
    assert_eq!(written.command.steps, Some(8));
    let check = report.walk_check.expect("the walk checked");
    assert_eq!(check.tries.len(), 1, "{:?}", check.tries);
    assert_eq!(check.completed(), check.tries.first());
    walks_its_eight_steps_and_the_stop(&scenario);
    std::fs::remove_dir_all(dir).unwrap();
}

/// The walk check where no height walks: the mini biped falls at every `walking.com_height`
/// tried, so `init` runs its walk at the standing CoM height and [`CHECK_LOWERING`] of it
/// lower each time, [`CHECK_TRIES`] runs, and writes the standing height back;
/// `skip_walk_check` writes without a run.
#[test]
fn a_walk_that_completes_at_no_height_is_written_at_the_standing_height() {
    use sea_sim::init::walking::{CHECK_LOWERING, CHECK_TRIES};
    let dir = folder("mini_walk");
    let foot = FootRectangle {
        x: [-0.05, 0.05],
        y: [-0.03, 0.03],
    };
    let options = InitOptions {
        walking: true,
        out: dir.join("mini_walk.toml"),
        ..mini_biped_options(&dir, foot)
    };
    let report = init(&options).unwrap();
    let check = report.walk_check.expect("the walk checked");
    assert_eq!(check.tries.len(), CHECK_TRIES, "{:?}", check.tries);
    assert!(check.completed().is_none() && !check.interrupted());
    let standing = report.walking_figures.com_height;
    for (k, run) in check.tries.iter().enumerate() {
        let lowered = standing * (1.0 - k as f64 * CHECK_LOWERING);
        assert!((run.com_height - lowered).abs() <= 1e-3, "{run}: {lowered}");
        assert!(run.status == "fell" || run.status == "diverged", "{run}");
        assert!(!run.reason.is_empty() && run.to_string().contains(&run.reason));
    }
    let written = Scenario::from_file(&options.out, &[]).unwrap();
    let written = written.walking.expect("[walking]").com_height;
    assert!(
        (written - standing).abs() <= 5e-4,
        "{written} against {standing}"
    );
    let skipped = InitOptions {
        skip_walk_check: true,
        ..options
    };
    assert!(init(&skipped).unwrap().walk_check.is_none());
    std::fs::remove_dir_all(dir).unwrap();
}

/// The walk check on a file that does not run: the run's error is the check's one run (status
/// `error`, the file named), the check ends and the settings keep the standing height.
#[test]
fn a_walk_that_cannot_be_run_ends_the_check_with_its_error() {
    use sea_sim::init::walking::{check_walk, RUN_FAILED};
    let dir = folder("walk_check_error");
    let out = dir.join("broken_walk.toml");
    std::fs::write(&out, "[walking\n").unwrap();
    let mut settings = sea_ctrl::walking::WalkingSettings::default();
    let standing = settings.com_height;
    let never = std::sync::atomic::AtomicBool::new(false);
    let mut rewrites = 0;
    let check = check_walk(
        &out,
        &mut settings,
        |_| {
            rewrites += 1;
            Ok(())
        },
        &never,
    )
    .unwrap();
    let [run] = check.tries.as_slice() else {
        panic!("one run expected: {:?}", check.tries);
    };
    assert_eq!(run.status, RUN_FAILED);
    assert!(run.reason.contains("broken_walk.toml"), "{run}");
    assert_eq!(check.failed(), Some(run));
    assert!(check.completed().is_none() && !check.interrupted());
    assert_eq!((settings.com_height, rewrites), (standing, 0));
    std::fs::remove_dir_all(dir).unwrap();
}

/// The walk check where the standing height does not walk: the G1 of example-robot-data
/// diverges at its standing CoM height (its stance knee straight on its stop at mid-stance)
/// and walks lower; `init` writes the first height that completed, and the file it wrote walks
/// its 8 steps and the stop. Needs example-robot-data (without it, says so and checks nothing).
#[test]
fn the_walk_check_lowers_the_com_height_of_the_g1_until_it_walks() {
    let Some(urdf) = crate::support::robot("g1_description/urdf/g1_29dof_rev_1_0.urdf") else {
        eprintln!("example-robot-data is not installed: the G1 walk check is not tested");
        return;
    };
    let dir = folder("g1_walk");
    let options = InitOptions {
        urdf: urdf.display().to_string(),
        contacts: [
            "left_ankle_roll_link:0,0,-0.035".into(),
            "right_ankle_roll_link:0,0,-0.035".into(),
        ],
        package_dirs: urdf
            .ancestors()
            .skip(3)
            .take(3)
            .map(Path::to_path_buf)
            .collect(),
        walking: true,
        out: dir.join("g1_walk.toml"),
        ..Default::default()
    };
    let report = init(&options).unwrap();
    let check = report.walk_check.expect("the walk checked");
    let chosen = check.completed().expect("a height that walks").clone();
    assert!(check.tries.len() >= 2, "{:?}", check.tries);
    assert!(chosen.com_height < report.walking_figures.com_height);
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    assert_eq!(
        scenario.walking.as_ref().unwrap().com_height,
        chosen.com_height
    );
    walks_its_eight_steps_and_the_stop(&scenario);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `[walking]` in an init scenario takes the defaults scaled to the robot for the keys it
/// leaves out: the iCub written by init with only `[walking.command]` walks on a pendulum of
/// its own CoM height and at its own feet's distance, not the iCub-sized defaults'.
#[test]
fn walking_keys_left_out_take_the_defaults_scaled_to_the_robot() {
    use sea_ctrl::walking::WalkingSettings;
    let dir = folder("icub_walk_defaults");
    let options = InitOptions {
        walking: true,
        out: dir.join("icub_walk.toml"),
        ..icub_options(&dir)
    };
    let report = init(&options).unwrap();
    let text = std::fs::read_to_string(&options.out).unwrap();
    let mut root: toml::Table = toml::from_str(&text).unwrap();
    let walking = root["walking"].as_table_mut().unwrap();
    walking.retain(|key, _| key == "command");
    std::fs::write(&options.out, toml::to_string(&root).unwrap()).unwrap();
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    let setup = build(&scenario).unwrap();
    let gait = setup.controller.gait().expect("walking");
    let figures = report.walking_figures;
    let scaled = WalkingSettings::scaled_to(&figures).unwrap();
    let gravity = setup.model.gravity.norm();
    let omega = (gravity / scaled.com_height).sqrt();
    assert!((gait.dcm.lip().omega - omega).abs() < 1e-9);
    assert!((scaled.com_height - WalkingSettings::default().com_height).abs() > 0.01);
    let last = gait.footsteps.final_stance();
    let width = (last.left.world_p_sole - last.right.world_p_sole).norm();
    assert!((width - figures.feet_distance).abs() < 1e-9, "{width}");
    assert!((gait.swings[0].height - scaled.swing_height).abs() < 1e-12);
    std::fs::remove_dir_all(dir).unwrap();
}

/// The motors of a robot set up by init are limited by its URDF's efforts
/// (`actuators.torque_limit_from_urdf`): the iCub's knee 37 Nm through the ratio 0.01, in the
/// scenario and in the walking scenario. With a knee effort below the torque the knee holds
/// standing, the report warns naming the joint and both figures.
#[test]
fn the_written_motors_are_limited_by_the_urdf_efforts_and_a_weak_joint_is_named() {
    let dir = folder("icub_limits");
    for walking in [false, true] {
        let options = InitOptions {
            walking,
            out: dir.join(format!("icub_{walking}.toml")),
            ..icub_options(&dir)
        };
        let report = init(&options).unwrap();
        assert!(report.warnings.iter().all(|w| !w.contains("effort")));
        let setup = build(&Scenario::from_file(&options.out, &[]).unwrap()).unwrap();
        let knee = setup.model.joint_index("l_knee").unwrap();
        let sea_dyn::Actuator::Elastic(p) = setup.plant.actuation.actuators[knee] else {
            panic!("the knee is elastic");
        };
        let limit = p.torque_limit.unwrap();
        assert!((limit - 0.37).abs() < 1e-12, "{limit}");
    }
    let urdf = dir.join("weak_knee.urdf");
    let text = std::fs::read_to_string(icub_urdf()).unwrap();
    let knee_limit = "<limit effort=\"37.0\" lower=\"-2.1642082724729685\"";
    assert_eq!(text.matches(knee_limit).count(), 2, "both knees' limits");
    let (head, tail) = text.split_at(text.find("<joint name=\"l_knee\"").unwrap());
    let weak = tail.replacen(
        knee_limit,
        "<limit effort=\"0.5\" lower=\"-2.1642082724729685\"",
        1,
    );
    std::fs::write(&urdf, format!("{head}{weak}")).unwrap();
    let options = InitOptions {
        urdf: urdf.display().to_string(),
        out: dir.join("weak.toml"),
        ..icub_options(&dir)
    };
    let report = init(&options).unwrap();
    let named: Vec<_> = report
        .warnings
        .iter()
        .filter(|w| w.contains("effort"))
        .collect();
    assert_eq!(named.len(), 1, "{:?}", report.warnings);
    assert!(
        named[0].contains("'l_knee'") && named[0].contains("0.5 Nm"),
        "{}",
        named[0]
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// A robot lighter than the iCub gets the QP's minimum normal force scaled down with its mass:
/// the mini biped at a fifth of its masses (1.7 kg, 16.7 N) could not carry the default 10 N
/// on each foot, and its written scenario was refused by `run`.
#[test]
fn a_light_robot_gets_a_minimum_normal_force_its_weight_can_carry() {
    let dir = folder("light_biped");
    // Every mass and moment of inertia a fifth: the same shapes, a fifth of the weight.
    let options = edited_mini_biped(&dir, |text| scale_masses(text, 0.2));
    init(&options).unwrap();
    let scenario = Scenario::from_file(&options.out, &[]).unwrap();
    let setup = build(&scenario).expect("the written scenario builds");
    let weight = setup.model.total_mass() * 9.81;
    let force = scenario.controller.contact.min_normal_force;
    assert!(
        force > 0.0 && 2.0 * force < weight,
        "{force} N for a weight of {weight} N"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `text` with every `value`, `ixx` ... `izz` attribute of its `<mass>` and `<inertia>`
/// elements multiplied by `factor`.
fn scale_masses(text: &str, factor: f64) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    let names = ["value", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"];
    while let Some(at) = rest.find("=\"") {
        let name_start = rest[..at].rfind(char::is_whitespace).map_or(0, |k| k + 1);
        let name = &rest[name_start..at];
        let value_end = at + 2 + rest[at + 2..].find('"').unwrap();
        let value = &rest[at + 2..value_end];
        out.push_str(&rest[..at + 2]);
        match value.parse::<f64>() {
            Ok(number) if names.contains(&name) => out.push_str(&format!("{}", number * factor)),
            _ => out.push_str(value),
        }
        rest = &rest[value_end..];
    }
    out.push_str(rest);
    out
}

/// `--walking` on two soles that coincide standing (both hips on the body's plane) names
/// `--contacts` and the distance; it named an internal figure (`walking figures:
/// feet_distance`).
#[test]
fn walking_on_soles_that_coincide_is_refused_naming_the_contacts() {
    let dir = folder("feet_same");
    let options = InitOptions {
        walking: true,
        ..edited_mini_biped(&dir, |text| {
            let same = text
                .replace("<origin xyz=\"0 0.06 -0.05\"", "<origin xyz=\"0 0 -0.05\"")
                .replace("<origin xyz=\"0 -0.06 -0.05\"", "<origin xyz=\"0 0 -0.05\"");
            assert_ne!(same, text, "the hips moved");
            same
        })
    };
    let message = init(&options).unwrap_err().to_string();
    assert!(
        message.contains("--contacts") && message.contains("0.0000 m apart"),
        "{message}"
    );
    assert!(!options.out.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// A foot measured from a collision box without width is refused naming the contact and the
/// measured rectangle (it named `--foot` with the rectangles' debug text), and a NaN size
/// names the link (it said the link had no collision geometry).
#[test]
fn a_measured_sole_without_area_or_with_a_nan_size_is_named() {
    let with_left_box = |size: &'static str| {
        move |text: &str| {
            let collision = format!(
                "<collision><origin xyz=\"0.02 0 -0.03\" rpy=\"0 0 0\"/><geometry><box \
                 size=\"{size}\"/></geometry></collision>\n  </link>\n\n  <joint \
                 name=\"l_sole_fixed_joint\""
            );
            let edited = text.replacen(
                "</link>\n\n  <joint name=\"l_sole_fixed_joint\"",
                &collision,
                1,
            );
            assert_ne!(edited, text, "the left foot's link end moved");
            edited
        }
    };
    for (size, expected) in [
        (
            "0.16 0 0.03",
            "cannot measure the foot of 'l_sole': its sole (the collision points within 0.01 m \
             of the lowest) measures x [-0.06, 0.1] y [0, 0] m, no area",
        ),
        (
            "nan 0.08 0.03",
            "cannot measure the foot of 'l_sole': link 'l_foot': a collision box of size [NaN, \
             0.08, 0.03]: finite, non-negative numbers expected",
        ),
    ] {
        let dir = folder("foot_without_area");
        let options = InitOptions {
            foot: None,
            ..edited_mini_biped(&dir, with_left_box(size))
        };
        let message = init(&options).unwrap_err().to_string();
        assert!(message.contains(expected), "{message}");
        assert!(!options.out.exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}

/// Options for the mini biped's URDF edited by `edit`, written as `robot.urdf` into `dir`, on
/// soles of the rectangle its feet hold.
fn edited_mini_biped(dir: &Path, edit: impl FnOnce(&str) -> String) -> InitOptions {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf/mini_biped.urdf"),
    )
    .unwrap();
    let urdf = dir.join("robot.urdf");
    std::fs::write(&urdf, edit(&text)).unwrap();
    let foot = FootRectangle {
        x: [-0.06, 0.1],
        y: [-0.04, 0.04],
    };
    InitOptions {
        urdf: urdf.display().to_string(),
        ..mini_biped_options(dir, foot)
    }
}
