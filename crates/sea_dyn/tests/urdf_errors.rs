//! URDF loading: every malformed description is an `Error::Model` naming the offending
//! element; physically doubtful ones load with warnings naming it (strict loading refuses
//! them); reduced models (locked joints) and reordered joint lists agree with the full model.

use crate::common;

use common::*;
use nalgebra::{DMatrix, DVector};
use sea_dyn::{
    bias_forces, centroidal_momentum_matrix, crba, frame_jacobian, frame_placement, gravity_forces,
    Data, Error, LoadOptions, Model, WarningKind,
};
use std::collections::HashMap;

fn link(name: &str) -> String {
    link_with(name, "1", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0")
}

#[allow(clippy::too_many_arguments)]
fn link_with(
    name: &str,
    mass: &str,
    ixx: &str,
    ixy: &str,
    ixz: &str,
    iyy: &str,
    iyz: &str,
    izz: &str,
    xyz: &str,
) -> String {
    format!(
        r#"<link name="{name}"><inertial><origin xyz="{xyz}" rpy="0 0 0"/><mass value="{mass}"/>
  <inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}" iyy="{iyy}" iyz="{iyz}" izz="{izz}"/></inertial></link>"#
    )
}

fn massless(name: &str) -> String {
    format!(r#"<link name="{name}"/>"#)
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    joint_with(name, kind, parent, child, "0 0 0.1", "0 0 1")
}

fn joint_with(name: &str, kind: &str, parent: &str, child: &str, xyz: &str, axis: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><origin xyz="{xyz}" rpy="0 0 0"/>
  <parent link="{parent}"/><child link="{child}"/><axis xyz="{axis}"/>
  <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>"#
    )
}

fn robot(parts: &[String]) -> String {
    format!("<robot name=\"bad\">\n{}\n</robot>", parts.join("\n"))
}

/// A valid three-link chain torso -> thigh -> shin, plus a massless fixed `sole`.
fn valid_parts() -> Vec<String> {
    vec![
        link("torso"),
        link("thigh"),
        link("shin"),
        massless("sole"),
        joint("hip", "revolute", "torso", "thigh"),
        joint("knee", "continuous", "thigh", "shin"),
        joint("ankle_fixed", "fixed", "shin", "sole"),
    ]
}

/// Replaces the part that starts like `prefix` (e.g. `<link name="thigh"`).
fn replace(parts: &[String], prefix: &str, new: String) -> Vec<String> {
    let mut out = parts.to_vec();
    let k = out
        .iter()
        .position(|p| p.starts_with(prefix))
        .unwrap_or_else(|| panic!("no part {prefix}"));
    out[k] = new;
    out
}

#[track_caller]
fn expect_model_error(text: &str, options: &LoadOptions, names: &[&str]) -> String {
    match Model::from_urdf_str(text, options) {
        Ok(_) => panic!("accepted a malformed URDF (expected an error naming {names:?}):\n{text}"),
        Err(error @ Error::Model { .. }) => {
            let msg = error.to_string();
            for name in names {
                assert!(msg.contains(name), "message {msg:?} does not name '{name}'");
            }
            msg
        }
        Err(other) => panic!("expected Error::Model naming {names:?}, got {other:?}"),
    }
}

#[track_caller]
fn expect_error(parts: &[String], names: &[&str]) -> String {
    expect_model_error(&robot(parts), &LoadOptions::default(), names)
}

#[test]
fn the_valid_reference_robot_loads() {
    let model = Model::from_urdf_str(&robot(&valid_parts()), &LoadOptions::default()).unwrap();
    assert_eq!(model.joint_names, vec!["hip", "knee"]);
    assert_eq!(model.frames.len(), 4);
    assert_eq!(model.base_link, "torso");
    assert!((model.total_mass() - 3.0).abs() < 1e-15);
}

/// The reference robot with the knee's parent a link that does not exist (`phantom`).
fn phantom_parent() -> Vec<String> {
    replace(
        &valid_parts(),
        r#"<joint name="knee""#,
        joint("knee", "continuous", "phantom", "shin"),
    )
}

#[test]
fn missing_links_are_named() {
    let parts = replace(
        &valid_parts(),
        r#"<joint name="knee""#,
        joint("knee", "continuous", "thigh", "ghost_link"),
    );
    // `shin` then has no parent either; the missing child must be reported, by name.
    expect_error(&parts, &["ghost_link", "knee"]);
    expect_error(&phantom_parent(), &["phantom", "knee"]);
}

#[test]
fn a_model_error_from_a_file_names_the_file() {
    let parts = phantom_parent();
    let path = std::env::temp_dir().join(format!("sea_dyn_model_file_{}.urdf", std::process::id()));
    std::fs::write(&path, robot(&parts)).unwrap();
    let loaded = Model::from_urdf_file(&path, &LoadOptions::default());
    std::fs::remove_file(&path).unwrap();
    let Err(error @ Error::Model { .. }) = loaded else {
        panic!("expected Error::Model, got {loaded:?}");
    };
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("{}: joint 'knee'", path.display())),
        "{message}"
    );
    let Error::Model { file, .. } = error else {
        unreachable!()
    };
    assert_eq!(file.as_deref(), Some(path.as_path()));
}

#[test]
fn loops_are_rejected() {
    // A link that is the child of two joints.
    let mut parts = valid_parts();
    parts.push(joint("shortcut", "revolute", "torso", "shin"));
    let msg = expect_error(&parts, &["shin", "shortcut"]);
    assert!(msg.contains("loop"), "{msg}");
    // A cycle with no root at all.
    let parts = vec![
        link("ring_a"),
        link("ring_b"),
        joint("ab", "revolute", "ring_a", "ring_b"),
        joint("ba", "revolute", "ring_b", "ring_a"),
    ];
    let msg = expect_error(&parts, &["ring_a"]);
    assert!(msg.contains("loop"), "{msg}");
    // A cycle detached from the root.
    let mut parts = valid_parts();
    parts.extend([
        link("island_a"),
        link("island_b"),
        joint("island_ab", "revolute", "island_a", "island_b"),
        joint("island_ba", "revolute", "island_b", "island_a"),
    ]);
    let msg = expect_error(&parts, &["island_"]);
    assert!(msg.contains("loop"), "{msg}");
}

#[test]
fn several_roots_are_named() {
    let mut parts = valid_parts();
    parts.push(link("orphan"));
    expect_error(&parts, &["torso", "orphan"]);
}

#[test]
fn unusable_masses_and_inertias_are_named() {
    let base = valid_parts();
    let key = r#"<link name="thigh""#;
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "negative mass",
            link_with("thigh", "-1", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0"),
            "negative mass",
        ),
        (
            "NaN mass",
            link_with("thigh", "nan", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0"),
            "non-finite",
        ),
        (
            "NaN inertia",
            link_with("thigh", "1", "0.1", "NaN", "0", "0.1", "0", "0.1", "0 0 0"),
            "non-finite",
        ),
        (
            "NaN inertial origin",
            link_with("thigh", "1", "0.1", "0", "0", "0.1", "0", "0.1", "0 nan 0"),
            "non-finite",
        ),
        (
            "infinite inertial origin",
            link_with("thigh", "1", "0.1", "0", "0", "0.1", "0", "0.1", "inf 0 0"),
            "non-finite",
        ),
        (
            "a mass of 1e308 kg (finite, but M(q) overflows)",
            link_with(
                "thigh", "1e308", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0",
            ),
            "beyond the 1e9",
        ),
        (
            "an inertia of 1e200",
            link_with("thigh", "1", "1e200", "0", "0", "0.1", "0", "0.1", "0 0 0"),
            "beyond the 1e9",
        ),
        (
            "an inertial origin 1e12 m away",
            link_with("thigh", "1", "0.1", "0", "0", "0.1", "0", "0.1", "1e12 0 0"),
            "beyond the 1e9",
        ),
    ];
    for (what, new, reason) in cases {
        let parts = replace(&base, key, new);
        let msg = std::panic::catch_unwind(|| expect_error(&parts, &["thigh", reason]))
            .unwrap_or_else(|_| panic!("case '{what}' failed"));
        eprintln!("{what}: {msg}");
    }
}

/// Physically doubtful inertias used to be refused; like Pinocchio (and MuJoCo with its
/// balancing off) they now load, each with a warning naming the link and what is wrong, and
/// strict loading refuses them with that same message as an `Error::Model`.
#[test]
fn doubtful_inertias_warn_and_strict_loading_refuses_them() {
    let base = valid_parts();
    let key = r#"<link name="thigh""#;
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    let cases: Vec<(&str, String, WarningKind, &str)> = vec![
        (
            "zero mass, nonzero inertia",
            link_with("thigh", "0", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0"),
            WarningKind::ZeroMassWithInertia,
            "zero mass",
        ),
        (
            "negative moment",
            link_with("thigh", "1", "-0.1", "0", "0", "0.1", "0", "0.1", "0 0 0"),
            WarningKind::InertiaNotPositiveSemidefinite,
            "positive semidefinite",
        ),
        (
            "indefinite (off-diagonal)",
            link_with("thigh", "1", "0.1", "0.2", "0", "0.1", "0", "0.1", "0 0 0"),
            WarningKind::InertiaNotPositiveSemidefinite,
            "positive semidefinite",
        ),
        (
            "zero inertia, positive mass",
            link_with("thigh", "1", "0", "0", "0", "0", "0", "0", "0 0 0"),
            WarningKind::SingularInertia,
            "point mass",
        ),
        (
            "triangle inequality",
            link_with("thigh", "1", "0.1", "0", "0", "0.1", "0", "0.5", "0 0 0"),
            WarningKind::TriangleInequality,
            "triangle",
        ),
        // Rotated version of principal moments (0.1, 0.1, 0.5): still violates it.
        (
            "triangle inequality, rotated",
            link_with("thigh", "1", "0.3", "0.2", "0", "0.3", "0", "0.1", "0 0 0"),
            WarningKind::TriangleInequality,
            "triangle",
        ),
    ];
    for (what, new, kind, reason) in cases {
        let text = robot(&replace(&base, key, new));
        let model = Model::from_urdf_str(&text, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("case '{what}' refused: {e}"));
        let [warning] = model.warnings.as_slice() else {
            panic!(
                "case '{what}': expected one warning, got {:?}",
                model.warnings
            );
        };
        assert_eq!(warning.kind, kind, "case '{what}'");
        assert_eq!(warning.element, "link 'thigh'", "case '{what}'");
        assert!(warning.message.contains(reason), "case '{what}': {warning}");
        let msg = expect_model_error(&text, &strict, &["thigh", reason]);
        assert_eq!(msg, warning.to_string(), "case '{what}'");
    }
    // A massless link with zero inertia is fine, silently; so is a tight but valid inertia.
    let massless_thigh = link_with("thigh", "0", "0", "0", "0", "0", "0", "0", "0 0 0");
    let tight_thigh = link_with("thigh", "1", "0.1", "0", "0", "0.1", "0", "0.2", "0 0 0");
    for new in [massless_thigh, tight_thigh] {
        // A massless thigh is a massless moving link: it carries shin, so M(q) is regular.
        let parts = replace(&base, key, new);
        let model = Model::from_urdf_str(&robot(&parts), &strict).unwrap();
        assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    }
}

/// A moving joint whose whole subtree is massless (Romeo's fingers) gives M(q) a zero row:
/// it loads, as in Pinocchio, with one warning naming the topmost such joint.
#[test]
fn a_massless_moving_subtree_warns_once_at_its_top() {
    let with_fingers = |kind: &str| {
        let mut parts = valid_parts();
        parts.extend([
            massless("finger_1"),
            massless("finger_2"),
            joint("finger_base", kind, "shin", "finger_1"),
            joint("finger_tip", kind, "finger_1", "finger_2"),
        ]);
        robot(&parts)
    };
    let text = with_fingers("revolute");
    let model = Model::from_urdf_str(&text, &LoadOptions::default()).unwrap();
    assert_eq!(model.n_joints(), 4);
    let [warning] = model.warnings.as_slice() else {
        panic!("expected one warning, got {:?}", model.warnings);
    };
    assert_eq!(warning.kind, WarningKind::MasslessSubtree);
    assert_eq!(warning.element, "joint 'finger_base'");
    assert!(warning.message.contains("singular"), "{warning}");
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    expect_model_error(&text, &strict, &["finger_base", "moves no mass"]);
    // The same links on fixed joints are frames of shin, without a warning.
    let model = Model::from_urdf_str(&with_fingers("fixed"), &LoadOptions::default()).unwrap();
    assert_eq!(model.n_joints(), 2);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}

/// Elements without dynamics that `urdf-rs` refuses are ignored: an empty `<texture />` in a
/// material (iCubGenova03); a robot without a name. A robot without links is an error.
#[test]
fn empty_textures_and_nameless_robots_load() {
    let material = r#"<material name="grey"><color rgba="0.5 0.5 0.5 1"/><texture /></material>"#;
    let visual =
        format!(r#"<visual><geometry><box size="0.1 0.1 0.1"/></geometry>{material}</visual>"#);
    let text = robot(&valid_parts())
        .replace("<robot name=\"bad\">", &format!("<robot>\n{material}"))
        .replace(
            r#"<link name="torso"><inertial>"#,
            &format!(r#"<link name="torso">{visual}<inertial>"#),
        )
        .replace(
            r#"<link name="sole"/>"#,
            r#"<link name="sole"><visual><geometry><sphere radius="0.1"/></geometry>
  <material name="m"><texture>
  </texture></material></visual></link>"#,
        );
    assert_eq!(text.matches("<texture").count(), 3, "{text}");
    let model = Model::from_urdf_str(&text, &LoadOptions::default()).unwrap();
    assert_eq!(model.joint_names, vec!["hip", "knee"]);
    assert_eq!(model.name, "");
    // A texture with a file is left to the parser.
    let with_file = text.replacen("<texture />", r#"<texture filename="wood.png"/>"#, 1);
    Model::from_urdf_str(&with_file, &LoadOptions::default()).unwrap();
    // Malformed XML after a removed texture is still a parse error.
    let broken = text.replace("</robot>", "<link name=\n</robot>");
    let error = Model::from_urdf_str(&broken, &LoadOptions::default()).unwrap_err();
    assert!(matches!(error, Error::Parse { .. }), "{error:?}");
    let empty = "<robot name=\"empty\">\n</robot>";
    expect_model_error(empty, &LoadOptions::default(), &["robot", "no links"]);
}

#[test]
fn bad_joint_numbers_are_named() {
    let base = valid_parts();
    let key = r#"<joint name="hip""#;
    let cases = [
        (
            "NaN in origin xyz",
            joint_with("hip", "revolute", "torso", "thigh", "0 NaN 0.1", "0 0 1"),
            "non-finite",
        ),
        (
            "NaN in axis",
            joint_with("hip", "revolute", "torso", "thigh", "0 0 0.1", "0 nan 1"),
            "non-finite",
        ),
        (
            "zero axis, revolute",
            joint_with("hip", "revolute", "torso", "thigh", "0 0 0.1", "0 0 0"),
            "zero axis",
        ),
        (
            "zero axis, continuous",
            joint_with("hip", "continuous", "torso", "thigh", "0 0 0.1", "0 0 0"),
            "zero axis",
        ),
        (
            "zero axis, prismatic",
            joint_with("hip", "prismatic", "torso", "thigh", "0 0 0.1", "0 0 0"),
            "zero axis",
        ),
        (
            "floating joint",
            joint("hip", "floating", "torso", "thigh"),
            "unsupported",
        ),
        (
            "planar joint",
            joint("hip", "planar", "torso", "thigh"),
            "unsupported",
        ),
    ];
    for (what, new, reason) in cases {
        let parts = replace(&base, key, new);
        let msg = std::panic::catch_unwind(|| expect_error(&parts, &["hip", reason]))
            .unwrap_or_else(|_| panic!("case '{what}' failed"));
        eprintln!("{what}: {msg}");
    }
    // NaN in an rpy.
    let text = robot(&base).replace(
        r#"<joint name="hip" type="revolute"><origin xyz="0 0 0.1" rpy="0 0 0"/>"#,
        r#"<joint name="hip" type="revolute"><origin xyz="0 0 0.1" rpy="0 nan 0"/>"#,
    );
    assert!(text.contains("0 nan 0"));
    expect_model_error(&text, &LoadOptions::default(), &["hip"]);
}

#[test]
fn a_zero_axis_on_a_fixed_joint_is_accepted() {
    let parts = replace(
        &valid_parts(),
        r#"<joint name="ankle_fixed""#,
        joint_with("ankle_fixed", "fixed", "shin", "sole", "0 0 -0.1", "0 0 0"),
    );
    let model = Model::from_urdf_str(&robot(&parts), &LoadOptions::default()).unwrap();
    assert_eq!(model.n_joints(), 2);
    assert!(model.frame_id("sole").is_ok());
}

#[test]
fn duplicate_names_are_named() {
    let mut parts = valid_parts();
    parts.push(link("shin"));
    let msg = expect_error(&parts, &["shin"]);
    assert!(msg.contains("duplicate"), "{msg}");
    let mut parts = valid_parts();
    parts.push(link("calf"));
    parts.push(joint("knee", "revolute", "shin", "calf"));
    let msg = expect_error(&parts, &["knee"]);
    assert!(msg.contains("duplicate"), "{msg}");
}

#[test]
fn bad_joint_lists_are_named() {
    let text = robot(&valid_parts());
    let opts = |joints: &[&str], locked: &[(&str, f64)]| LoadOptions {
        joints: Some(joints.iter().map(|s| s.to_string()).collect()),
        locked: locked.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        ..Default::default()
    };
    expect_model_error(&text, &opts(&["hip", "elbow"], &[]), &["elbow"]);
    expect_model_error(&text, &opts(&["hip", "ankle_fixed"], &[]), &["ankle_fixed"]);
    expect_model_error(&text, &opts(&["knee", "hip", "knee"], &[]), &["knee"]);
    expect_model_error(&text, &opts(&["hip"], &[("wrist", 0.3)]), &["wrist"]);
    expect_model_error(&text, &opts(&["hip"], &[("hip", 0.3)]), &["hip"]);
    expect_model_error(
        &text,
        &opts(&["hip"], &[("ankle_fixed", 0.3)]),
        &["ankle_fixed"],
    );
    expect_model_error(&text, &opts(&["hip"], &[("knee", f64::NAN)]), &["knee"]);
    // Valid: an empty list locks everything; a locked value for an unlisted joint.
    let model = Model::from_urdf_str(&text, &opts(&[], &[("knee", 0.4)])).unwrap();
    assert_eq!(model.n_joints(), 0);
    assert_eq!(model.nv(), 6);
}

#[test]
fn unparsable_text_is_a_parse_error_and_a_missing_file_an_io_error() {
    assert!(matches!(
        Model::from_urdf_str("<robot", &LoadOptions::default()),
        Err(Error::Parse { file: None, .. })
    ));
    let path = "/nonexistent/dir/robot_that_is_not_here.urdf";
    match Model::from_urdf_file(path, &LoadOptions::default()) {
        Err(error @ Error::Io { .. }) => {
            let msg = error.to_string();
            assert!(msg.contains("robot_that_is_not_here.urdf"), "{msg}");
            assert!(msg.contains("No such file or directory"), "{msg}");
        }
        other => panic!("expected Error::Io, got {other:?}"),
    }
}

#[test]
fn unparsable_file_names_the_file() {
    let path = std::env::temp_dir().join(format!("sea_dyn_unparsable_{}.urdf", std::process::id()));
    std::fs::write(&path, "<robot name=\"r\">\n<link name=\"a\">\n</robot>\n").unwrap();
    let result = Model::from_urdf_file(&path, &LoadOptions::default());
    std::fs::remove_file(&path).unwrap();
    match result {
        Err(error @ Error::Parse { file: Some(_), .. }) => {
            let msg = error.to_string();
            assert!(msg.starts_with(&path.display().to_string()), "{msg}");
        }
        other => panic!("expected Error::Parse naming the file, got {other:?}"),
    }
}

#[test]
fn shipped_urdf_files_load() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "urdf") {
            let model = Model::from_urdf_file(&path, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(model.total_mass() > 0.0);
            n += 1;
        }
    }
    assert!(n > 0);
}

// ---------------------------------------------------------------------------------------------
// Joint lists: order, reduced models.

/// Depth-first joint order of a description (children in file order), written independently.
fn dfs_moving(desc: &RobotDesc) -> Vec<String> {
    fn visit(desc: &RobotDesc, link: usize, out: &mut Vec<String>) {
        for &j in &desc.joint_file_order {
            let joint = &desc.joints[j];
            if joint.parent == link {
                if joint.kind.moves() {
                    out.push(joint.name.clone());
                }
                visit(desc, joint.child, out);
            }
        }
    }
    let mut out = Vec::new();
    visit(desc, 0, &mut out);
    out
}

#[test]
fn default_joint_order_is_depth_first_in_file_order() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let model = load(&desc);
        assert_eq!(model.joint_names, dfs_moving(&desc), "seed {seed}");
    }
}

/// Maps reduced-model vectors into the full model: base as is, listed joints at their
/// coordinates, others at `locked` (configuration) or 0 (velocity).
fn to_full(
    full: &Model,
    reduced: &Model,
    v: &[f64],
    head: usize,
    locked: &HashMap<String, f64>,
) -> Vec<f64> {
    let mut out = v[..head].to_vec();
    for name in &full.joint_names {
        out.push(match reduced.joint_index(name) {
            Some(k) => v[head + k],
            None if head == 7 => locked.get(name).copied().unwrap_or(0.0),
            None => 0.0,
        });
    }
    out
}

/// Column/row indices of the reduced model's velocity in the full model's.
fn velocity_map(full: &Model, reduced: &Model) -> Vec<usize> {
    (0..6)
        .chain(
            reduced
                .joint_names
                .iter()
                .map(|n| 6 + full.joint_index(n).unwrap()),
        )
        .collect()
}

fn select(m: &DMatrix<f64>, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), cols.len(), |i, j| m[(rows[i], cols[j])])
}

fn select_rows(v: &DVector<f64>, rows: &[usize]) -> DVector<f64> {
    DVector::from_fn(rows.len(), |i, _| v[rows[i]])
}

/// Checks that `reduced` equals `full` at the locked values: M, h, G, A_G, every frame
/// placement and Jacobian.
fn check_reduced_against_full(
    seed: u64,
    desc: &RobotDesc,
    full: &Model,
    reduced: &Model,
    locked: &HashMap<String, f64>,
) {
    let mut df = Data::new(full);
    let mut dr = Data::new(reduced);
    let mut rng = Lcg::new(seed * 7 + 3);
    let q_r = random_q(&mut rng, reduced.nq());
    let nu_r = random_v(&mut rng, reduced.nv(), 1.0);
    let q_f = to_full(full, reduced, &q_r, 7, locked);
    let nu_f = to_full(full, reduced, &nu_r, 6, locked);
    let map = velocity_map(full, reduced);
    let ctx = format!("seed {seed}, joints {:?}", reduced.joint_names);

    let m_f = crba(full, &mut df, &q_f).clone();
    let m_r = crba(reduced, &mut dr, &q_r).clone();
    let scale = m_f.amax();
    assert_close_mat(
        &format!("{ctx}: M"),
        &m_r,
        &select(&m_f, &map, &map),
        1e-12,
        scale,
    );
    let h_f = bias_forces(full, &mut df, &q_f, &nu_f).clone();
    let h_r = bias_forces(reduced, &mut dr, &q_r, &nu_r).clone();
    assert_close_vec(
        &format!("{ctx}: h"),
        &h_r,
        &select_rows(&h_f, &map),
        1e-12,
        h_f.amax() + 1.0,
    );
    let g_f = gravity_forces(full, &mut df, &q_f).clone();
    let g_r = gravity_forces(reduced, &mut dr, &q_r).clone();
    assert_close_vec(
        &format!("{ctx}: G"),
        &g_r,
        &select_rows(&g_f, &map),
        1e-12,
        g_f.amax() + 1.0,
    );
    let a_f = centroidal_momentum_matrix(full, &mut df, &q_f).clone();
    let a_r = centroidal_momentum_matrix(reduced, &mut dr, &q_r).clone();
    let all6: Vec<usize> = (0..6).collect();
    assert_close_mat(
        &format!("{ctx}: A_G"),
        &a_r,
        &select(&a_f, &all6, &map),
        1e-12,
        a_f.amax(),
    );
    assert!((full.total_mass() - reduced.total_mass()).abs() < 1e-12 * full.total_mass());

    sea_dyn::forward_kinematics(full, &mut df, &q_f);
    sea_dyn::forward_kinematics(reduced, &mut dr, &q_r);
    for link in &desc.links {
        let (idf, idr) = (
            full.frame_id(&link.name).unwrap(),
            reduced.frame_id(&link.name).unwrap(),
        );
        let (pf, pr) = (
            frame_placement(full, &df, idf),
            frame_placement(reduced, &dr, idr),
        );
        assert!(
            (pf.rotation - pr.rotation).amax() < 1e-12
                && (pf.translation - pr.translation).amax() < 1e-12,
            "{ctx}: placement of {}",
            link.name
        );
    }
    for link in &desc.links {
        let (idf, idr) = (
            full.frame_id(&link.name).unwrap(),
            reduced.frame_id(&link.name).unwrap(),
        );
        let jf = frame_jacobian(full, &mut df, &q_f, idf).clone();
        let jr = frame_jacobian(reduced, &mut dr, &q_r, idr).clone();
        assert_close_mat(
            &format!("{ctx}: J of {}", link.name),
            &jr,
            &select(&jf, &all6, &map),
            1e-12,
            5.0,
        );
    }
}

#[test]
fn reduced_models_equal_the_full_model_at_the_locked_values() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let full = load(&desc);
        let mut rng = Lcg::new(20_000 + seed);
        let mut keep = Vec::new();
        let mut locked = HashMap::new();
        for name in desc.moving_joints() {
            if rng.chance(0.5) {
                keep.push(name);
            } else if rng.chance(0.8) {
                locked.insert(name, rng.range(-1.5, 1.5));
            } // else: locked at the default 0
        }
        shuffle(&mut rng, &mut keep);
        let options = LoadOptions {
            joints: Some(keep.clone()),
            locked: locked.clone(),
            ..Default::default()
        };
        let reduced = Model::from_urdf_str(&desc.to_urdf(), &options).unwrap();
        assert_eq!(
            reduced.joint_names, keep,
            "seed {seed}: coordinate order is the list order"
        );
        check_reduced_against_full(seed, &desc, &full, &reduced, &locked);
    }
}

#[test]
fn reordering_the_joint_list_permutes_the_dynamics() {
    for seed in seeds() {
        let desc = random_robot(seed);
        let full = load(&desc);
        let mut rng = Lcg::new(30_000 + seed);
        let mut order = desc.moving_joints();
        shuffle(&mut rng, &mut order);
        let options = LoadOptions {
            joints: Some(order.clone()),
            locked: HashMap::new(),
            ..Default::default()
        };
        let permuted = Model::from_urdf_str(&desc.to_urdf(), &options).unwrap();
        assert_eq!(permuted.joint_names, order);
        check_reduced_against_full(seed, &desc, &full, &permuted, &HashMap::new());
    }
}

/// A link with `<visual>` elements before and after its `<inertial>` (valid URDF, which urdfdom
/// reads and `urdf-rs` 0.10 refuses with "duplicate field `visual`") loads, as the same model
/// as the file with the inertial first, and keeps both visuals in order.
#[test]
fn visuals_around_the_inertial_load_as_the_sorted_file() {
    let visual =
        |size: &str| format!(r#"<visual><geometry><box size="{size}"/></geometry></visual>"#);
    let collision = r#"<collision><geometry><sphere radius="0.1"/></geometry></collision>"#;
    let (a, b) = (visual("0.1 0.1 0.1"), visual("0.2 0.2 0.2"));
    let torso = link("torso");
    let (start, rest) = torso.split_at(torso.find("<inertial>").unwrap());
    let (inertial, end) = rest.split_at(rest.find("</link>").unwrap());
    let mixed = format!("{start}{a}\n{collision}{inertial}{b}{collision}{end}");
    let sorted = format!("{start}{inertial}{a}\n{collision}{b}{collision}{end}");
    let text_of = |torso_link: &str| {
        let mut parts = valid_parts();
        parts[0] = torso_link.to_string();
        robot(&parts)
    };
    let options = LoadOptions::default();
    let error = urdf_rs::read_from_string(&text_of(&mixed)).unwrap_err();
    assert!(error.to_string().contains("duplicate field"), "{error}");
    let model = Model::from_urdf_str(&text_of(&mixed), &options).unwrap();
    assert_eq!(
        model,
        Model::from_urdf_str(&text_of(&sorted), &options).unwrap()
    );
    let robot = sea_dyn::urdf::parse_urdf(&text_of(&mixed)).unwrap();
    let boxes: Vec<_> = robot.links[0]
        .visual
        .iter()
        .map(|v| format!("{:?}", v.geometry))
        .collect();
    assert_eq!(boxes.len(), 2);
    assert!(
        boxes[0].contains("0.1") && boxes[1].contains("0.2"),
        "{boxes:?}"
    );
    assert_eq!(robot.links[0].collision.len(), 2);
}

#[test]
fn hostile_files_are_refused_quickly_and_named() {
    // Nested tens of thousands deep: refused before urdf-rs's recursive parser sees it.
    let deep = format!(
        "<robot name=\"r\">{}{}</robot>",
        "<a>".repeat(20_000),
        "</a>".repeat(20_000)
    );
    let error = Model::from_urdf_str(&deep, &LoadOptions::default()).unwrap_err();
    assert!(error.to_string().contains("nest 20001 deep"), "{error}");
    // A device, not a file: refused before a byte is read.
    let error = Model::from_urdf_file("/dev/zero", &LoadOptions::default()).unwrap_err();
    assert!(error.to_string().contains("not a regular file"), "{error}");
    // A number that is not one: its element, attribute and link named.
    let parts = replace(
        &valid_parts(),
        "<link name=\"shin\"",
        link_with("shin", "abc", "0.1", "0", "0", "0.1", "0", "0.1", "0 0 0"),
    );
    let error = Model::from_urdf_str(&robot(&parts), &LoadOptions::default()).unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("link 'shin' <mass value=\"abc\">: 'abc' is not a number"),
        "{message}"
    );
}

/// A limit with lower above upper loads as an unlimited joint, with a warning naming the
/// joint (refused under strict loading); URDF's default of no limit (0, 0) stays silent.
#[test]
fn inverted_joint_limits_warn_naming_the_joint() {
    let swapped = valid_parts()
        .iter()
        .map(|part| part.replace(r#"lower="-1" upper="1""#, r#"lower="1" upper="-1""#))
        .collect::<Vec<_>>();
    let text = robot(&swapped);
    let model = Model::from_urdf_str(&text, &LoadOptions::default()).unwrap();
    let [warning] = model.warnings.as_slice() else {
        panic!("expected one warning, got {:?}", model.warnings);
    };
    assert_eq!(warning.kind, WarningKind::InvertedLimits);
    assert_eq!(warning.element, "joint 'hip'");
    let hip = model.joint_names.iter().position(|n| n == "hip").unwrap();
    assert_eq!(
        model.joints[hip].position_limits,
        [f64::NEG_INFINITY, f64::INFINITY]
    );
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    expect_model_error(&text, &strict, &["hip", "lower 1 is above upper -1"]);
    let unset = valid_parts()
        .iter()
        .map(|part| part.replace(r#"lower="-1" upper="1""#, r#"lower="0" upper="0""#))
        .collect::<Vec<_>>();
    let model = Model::from_urdf_str(&robot(&unset), &LoadOptions::default()).unwrap();
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}

/// A moving joint that mimics another loads as a joint of its own, with a warning naming it,
/// the joint it mimics and the coupling (refused under strict loading); a fixed or locked
/// joint's mimic stays silent.
#[test]
fn a_mimic_joint_warns_that_its_coupling_is_not_modelled() {
    let mimic = r#"<mimic joint="hip" multiplier="-2" offset="0.5"/></joint>"#;
    let with_mimic = |name: &str| {
        valid_parts()
            .iter()
            .map(
                |part| match part.contains(&format!("<joint name=\"{name}\"")) {
                    true => part.replace("</joint>", mimic),
                    false => part.clone(),
                },
            )
            .collect::<Vec<_>>()
    };
    let text = robot(&with_mimic("knee"));
    let model = Model::from_urdf_str(&text, &LoadOptions::default()).unwrap();
    let [warning] = model.warnings.as_slice() else {
        panic!("expected one warning, got {:?}", model.warnings);
    };
    assert_eq!(warning.kind, WarningKind::MimicNotModelled);
    assert_eq!(warning.element, "joint 'knee'");
    assert!(
        warning
            .message
            .contains("mimics joint 'hip' (multiplier -2, offset 0.5)"),
        "{warning}"
    );
    assert_eq!(model.n_joints(), 2);
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    expect_model_error(&text, &strict, &["knee", "mimics joint 'hip'"]);
    let model = Model::from_urdf_str(&robot(&with_mimic("ankle_fixed")), &LoadOptions::default());
    assert!(model.unwrap().warnings.is_empty());
    // Locked (not among `joints`), the mimic joint is fixed: silent, also strictly.
    let hip_only = LoadOptions {
        joints: Some(vec!["hip".into()]),
        strict: true,
        ..Default::default()
    };
    let model = Model::from_urdf_str(&text, &hip_only).unwrap();
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}
