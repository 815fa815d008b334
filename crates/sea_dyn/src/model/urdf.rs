//! Building a [`Model`] from URDF (parsed by `urdf-rs`), with every unusable description
//! reported as [`Error::Model`] naming the link or joint and the violated condition (and the
//! file, [`Model::from_urdf_file`]), and every
//! physically doubtful but computable one as a [`Warning`] kept in [`Model::warnings`]
//! (refused in strict mode, [`LoadOptions::strict`]; the checks are in `inertia_check.rs`).
//!
//! Steps: parse; check names, numbers, joint types and inertias; build the link tree (one
//! root, no loops); walk it depth first (children in file order), starting a new body at every
//! moving joint and merging links attached by fixed or locked joints into their parent body.
//! Every link stays an addressable frame. URDF axes are normalised; a link without
//! `<inertial>`, or with zero mass and zero inertia, is massless: a frame of its body (as in
//! Pinocchio and MuJoCo). A massless link on a moving joint keeps its joint (zero inertia).

use crate::error::{Error, Result, Warning, WarningKind};
use crate::model::inertia_check::{check_link_inertia, massless_subtree_warnings};
use crate::model::urdf_numbers::first_bad_number;
use crate::model::{joint_motion, Frame, Joint, JointKind, Model};
use crate::spatial::{BodyInertia, Pose};
use nalgebra::{Matrix3, Vector3};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

/// The message of an [`Error::Model`] for a name of [`LoadOptions::joints`] that is not a
/// joint of the URDF (callers that took the list from a file name their key with it).
pub const UNKNOWN_LISTED_JOINT: &str = "unknown joint in the joint list";

/// Which joints move, in which order, and where the others are locked.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Moving joints in coordinate order; `None` means every revolute, continuous and prismatic
    /// joint in depth-first tree order.
    pub joints: Option<Vec<String>>,
    /// Values of locked joints (joints not in `joints`); unlisted locked joints are at 0.
    pub locked: HashMap<String, f64>,
    /// Refuse physically doubtful descriptions (the first [`Warning`] becomes an
    /// [`Error::Model`]) instead of loading them with warnings. Default `false`.
    pub strict: bool,
}

impl Model {
    /// Loads a URDF file; see [`Model::from_urdf_str`].
    pub fn from_urdf_file(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Model> {
        let path = path.as_ref();
        let text = crate::files::read_text(path).map_err(|e| Error::io(path, e))?;
        Self::from_urdf_str(&text, options).map_err(|e| e.in_file(path))
    }

    /// Builds a model from URDF text.
    pub fn from_urdf_str(text: &str, options: &LoadOptions) -> Result<Model> {
        build(&parse_urdf(text)?, options)
    }
}

/// The URDF text parsed by `urdf-rs`, as the model reads it (empty `<texture>` elements
/// tolerated, see `without_empty_textures`); for readers of the URDF's other parts (visuals).
///
/// Errors: [`Error::Parse`] when the text is not a URDF, or its elements nest deeper than
/// [`crate::files::MAX_XML_DEPTH`] (checked before `urdf-rs`, whose recursive parser would
/// overflow the stack).
pub fn parse_urdf(text: &str) -> Result<urdf_rs::Robot> {
    let depth = crate::files::xml_depth(text);
    if depth > crate::files::MAX_XML_DEPTH {
        return Err(Error::parse(format!(
            "cannot parse URDF: its elements nest {depth} deep, more than {}",
            crate::files::MAX_XML_DEPTH
        )));
    }
    let text = without_empty_textures(text);
    urdf_rs::read_from_string(&inertial_before_visuals(&text)).map_err(|e| {
        let message = first_bad_number(&text).unwrap_or_else(|| e.to_string());
        Error::parse(format!("cannot parse URDF: {message}"))
    })
}

/// The text with, in every `<link>` where an `<inertial>` follows a `<visual>`, that
/// `<inertial>` moved to just before the link's first `<visual>`.
///
/// Why: a workaround for `urdf-rs` 0.10, which refuses a valid link such as
/// `<visual/><inertial/><visual/>` with "duplicate field `visual`" (serde-xml-rs reads the
/// elements of one name only when they are contiguous; urdf-rs groups the `<collision>`
/// elements after the others but keeps `<inertial>` among the `<visual>` ones). urdfdom
/// (Pinocchio) reads children in any order. The order of the visuals, of the collisions and of
/// everything else is kept, so the model is the one of the reordered file. Text without such a
/// link (or that is not well-formed XML, left to urdf-rs to report) is returned unchanged; the
/// work is one parse and one copy, linear in the text.
fn inertial_before_visuals(text: &str) -> Cow<'_, str> {
    if !text.contains("<inertial") || !text.contains("<visual") {
        return Cow::Borrowed(text);
    }
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let Ok(document) = roxmltree::Document::parse_with_options(text, options) else {
        return Cow::Borrowed(text);
    };
    let mut edits = Vec::new();
    for link in document.root_element().children() {
        if link.has_tag_name("link") {
            inertial_moves(link, text, &mut edits);
        }
    }
    if edits.is_empty() {
        return Cow::Borrowed(text);
    }
    edits.sort_by_key(|edit| edit.0.start);
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    for (range, replacement) in edits {
        out.push_str(&text[copied..range.start]);
        out.push_str(&replacement);
        copied = range.end;
    }
    out.push_str(&text[copied..]);
    Cow::Owned(out)
}

/// Edits (byte range of `text`, its replacement) moving each `<inertial>` child of `link` that
/// follows a `<visual>` child to just before the first `<visual>`; the removed element leaves
/// its newlines, so that the lines after it keep their numbers.
fn inertial_moves(
    link: roxmltree::Node<'_, '_>,
    text: &str,
    edits: &mut Vec<(std::ops::Range<usize>, String)>,
) {
    let mut first_visual = None;
    for child in link.children().filter(|c| c.is_element()) {
        let range = child.range();
        if child.has_tag_name("visual") && first_visual.is_none() {
            first_visual = Some(range.start);
        }
        if let (true, Some(at)) = (child.has_tag_name("inertial"), first_visual) {
            edits.push((at..at, text[range.clone()].to_string()));
            edits.push((range.clone(), text[range].matches('\n').collect()));
        }
    }
}

/// The text without `<texture>` elements that have no `filename` attribute.
///
/// Why: `urdf-rs` 0.10 declares `Texture::filename` required and refuses the whole file on an
/// empty `<texture />` inside a visual `<material>`, which real files carry (iCub's
/// iCubGenova03, iCubLisboa01, iCubNancy01; Romeo's `romeo_laas_small`); urdfdom (Pinocchio)
/// ignores it. A texture without a file carries no dynamics, so only those elements are
/// removed, keeping their newlines so that parse errors keep their line numbers.
fn without_empty_textures(text: &str) -> Cow<'_, str> {
    let mut out = String::new();
    let mut copied = 0;
    let mut search = 0;
    while let Some(found) = text[search..].find("<texture") {
        let start = search + found;
        search = start + "<texture".len();
        let Some(span) = empty_texture_span(&text[start..]) else {
            continue;
        };
        out.push_str(&text[copied..start]);
        out.extend(text[start..start + span].matches('\n'));
        copied = start + span;
        search = copied;
    }
    if copied == 0 {
        return Cow::Borrowed(text);
    }
    out.push_str(&text[copied..]);
    Cow::Owned(out)
}

/// Length of the element at the start of `rest` (which starts with `<texture`) if it is a
/// texture without a `filename` attribute: `<texture/>` or `<texture ...>...</texture>`.
fn empty_texture_span(rest: &str) -> Option<usize> {
    let after_name = rest["<texture".len()..].chars().next()?;
    if !(after_name.is_whitespace() || after_name == '/' || after_name == '>') {
        return None; // another element, e.g. `<textures>`
    }
    let tag_end = rest.find('>')? + 1;
    let tag = &rest[..tag_end];
    if tag.contains("filename") {
        return None;
    }
    if tag.ends_with("/>") {
        return Some(tag_end);
    }
    let close = rest.find("</texture")?;
    Some(close + rest[close..].find('>')? + 1)
}

/// Largest magnitude of a URDF mass [kg], inertia [kg m^2], origin [m] or angle [rad] the
/// loader takes: far above any robot's, and far enough below the float range that the
/// algorithms' products (a mass times a squared lever arm, times a velocity) cannot overflow.
/// A larger number is a corrupt or hostile file.
pub const MAX_URDF_MAGNITUDE: f64 = 1e9;

/// Every number of `values` must be finite and at most [`MAX_URDF_MAGNITUDE`] in magnitude.
fn check_numbers(what: &str, values: &[f64]) -> Result<()> {
    if values.iter().any(|v| !v.is_finite()) {
        return Err(Error::model(
            what,
            format!("has a non-finite number: {values:?}"),
        ));
    }
    if let Some(huge) = values.iter().find(|v| v.abs() > MAX_URDF_MAGNITUDE) {
        return Err(Error::model(
            what,
            format!(
                "has the number {huge:e}, beyond the {MAX_URDF_MAGNITUDE:e} a robot's masses, \
                 inertias and lengths stay far below: {values:?}"
            ),
        ));
    }
    Ok(())
}

fn check_pose(what: &str, pose: &urdf_rs::Pose) -> Result<()> {
    check_numbers(&format!("{what} origin xyz"), &pose.xyz.0)?;
    check_numbers(&format!("{what} origin rpy"), &pose.rpy.0)
}

fn to_pose(pose: &urdf_rs::Pose) -> Pose {
    Pose::from_xyz_rpy(pose.xyz.0, pose.rpy.0)
}

/// The link's inertia in the link frame, after checking mass and inertia (doubts go to
/// `warnings`); `None` if massless.
fn link_inertia(link: &urdf_rs::Link, warnings: &mut Vec<Warning>) -> Result<Option<BodyInertia>> {
    let inertial = &link.inertial;
    let i = &inertial.inertia;
    let what = format!("link '{}'", link.name);
    check_pose(&format!("{what} inertial"), &inertial.origin)?;
    check_numbers(
        &format!("{what} inertial"),
        &[
            inertial.mass.value,
            i.ixx,
            i.ixy,
            i.ixz,
            i.iyy,
            i.iyz,
            i.izz,
        ],
    )?;
    let inertia = Matrix3::new(
        i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
    );
    let mass = inertial.mass.value;
    if !check_link_inertia(&what, mass, &inertia, warnings)? {
        return Ok(None);
    }
    let frame = to_pose(&inertial.origin);
    Ok(Some(BodyInertia {
        mass,
        com: frame.translation,
        inertia_com: frame.rotation * inertia * frame.rotation.transpose(),
    }))
}

fn joint_kind(joint: &urdf_rs::Joint) -> Result<Option<JointKind>> {
    use urdf_rs::JointType as T;
    match joint.joint_type {
        T::Revolute | T::Continuous => Ok(Some(JointKind::Revolute)),
        T::Prismatic => Ok(Some(JointKind::Prismatic)),
        T::Fixed => Ok(None),
        ref other => Err(Error::model(
            format!("joint '{}'", joint.name),
            format!("has unsupported type {other:?} (supported: revolute, continuous, prismatic, fixed)"),
        )),
    }
}

/// Checks one joint's numbers and returns its unit axis (meaningful for moving joints).
fn joint_axis(joint: &urdf_rs::Joint) -> Result<Vector3<f64>> {
    let what = format!("joint '{}'", joint.name);
    check_pose(&what, &joint.origin)?;
    let axis = Vector3::from(joint.axis.xyz.0);
    check_numbers(&format!("{what} axis"), &joint.axis.xyz.0)?;
    if joint.limit.lower.is_nan() || joint.limit.upper.is_nan() || joint.limit.effort.is_nan() {
        return Err(Error::model(what, "limit has a NaN"));
    }
    let norm = axis.norm();
    if norm < 1e-12 && joint.joint_type != urdf_rs::JointType::Fixed {
        return Err(Error::model(what, "has a zero axis"));
    }
    Ok(if norm > 0.0 { axis / norm } else { axis })
}

fn check_unique<'a>(kind: &str, names: impl Iterator<Item = &'a str>) -> Result<()> {
    let mut seen = std::collections::HashSet::new();
    for name in names {
        if !seen.insert(name) {
            return Err(Error::model(format!("{kind} '{name}'"), "duplicate name"));
        }
    }
    Ok(())
}

/// Link tree: children joints of each link (file order) and the root link.
struct Tree {
    children: Vec<Vec<usize>>,
    root: usize,
}

fn build_tree(robot: &urdf_rs::Robot, link_index: &HashMap<&str, usize>) -> Result<Tree> {
    let n_links = robot.links.len();
    if n_links == 0 {
        return Err(Error::model("robot", "has no links"));
    }
    let mut children = vec![Vec::new(); n_links];
    let mut parent_joint: Vec<Option<usize>> = vec![None; n_links];
    for (j, joint) in robot.joints.iter().enumerate() {
        let find = |role: &str, name: &str| {
            link_index.get(name).copied().ok_or_else(|| {
                Error::model(
                    format!("joint '{}'", joint.name),
                    format!("names {role} link '{name}', which does not exist"),
                )
            })
        };
        let parent = find("parent", &joint.parent.link)?;
        let child = find("child", &joint.child.link)?;
        if let Some(other) = parent_joint[child] {
            return Err(Error::model(
                format!("link '{}'", robot.links[child].name),
                format!(
                    "kinematic loop: the link is the child of joints '{}' and '{}'",
                    robot.joints[other].name, joint.name
                ),
            ));
        }
        parent_joint[child] = Some(j);
        children[parent].push(j);
    }
    let roots: Vec<usize> = (0..n_links)
        .filter(|l| parent_joint[*l].is_none())
        .collect();
    let root = match roots.as_slice() {
        [root] => *root,
        [] => {
            let name = robot.links.first().map(|l| l.name.as_str()).unwrap_or("");
            return Err(Error::model(
                "robot",
                format!("kinematic loop: every link has a parent joint (e.g. link '{name}'), no root link"),
            ));
        }
        many => {
            let names: Vec<&str> = many.iter().map(|l| robot.links[*l].name.as_str()).collect();
            return Err(Error::model(
                "robot",
                format!(
                    "several root links (links without a parent joint): {}",
                    names.join(", ")
                ),
            ));
        }
    };
    Ok(Tree { children, root })
}

/// Which joints move and their coordinate index; values of locked joints.
struct Actuation {
    coordinate: HashMap<usize, usize>,
    locked_value: HashMap<usize, f64>,
}

fn resolve_actuation(
    robot: &urdf_rs::Robot,
    kinds: &[Option<JointKind>],
    dfs_joints: &[usize],
    options: &LoadOptions,
) -> Result<Actuation> {
    let joint_index: HashMap<&str, usize> = robot
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.name.as_str(), i))
        .collect();
    let mut coordinate = HashMap::new();
    match &options.joints {
        Some(list) => {
            for (k, name) in list.iter().enumerate() {
                let j = *joint_index
                    .get(name.as_str())
                    .ok_or_else(|| Error::model(format!("joint '{name}'"), UNKNOWN_LISTED_JOINT))?;
                if kinds[j].is_none() {
                    return Err(Error::model(
                        format!("joint '{name}'"),
                        "in the joint list but fixed: it cannot move",
                    ));
                }
                if coordinate.insert(j, k).is_some() {
                    return Err(Error::model(
                        format!("joint '{name}'"),
                        "listed twice in the joint list",
                    ));
                }
            }
        }
        None => {
            for &j in dfs_joints.iter().filter(|j| kinds[**j].is_some()) {
                let k = coordinate.len();
                coordinate.insert(j, k);
            }
        }
    }
    let mut locked_value = HashMap::new();
    for (name, value) in &options.locked {
        let j = *joint_index
            .get(name.as_str())
            .ok_or_else(|| Error::model(format!("joint '{name}'"), "unknown locked joint"))?;
        if coordinate.contains_key(&j) || kinds[j].is_none() {
            return Err(Error::model(
                format!("joint '{name}'"),
                "cannot be locked: it is moving or fixed",
            ));
        }
        if !value.is_finite() {
            return Err(Error::model(
                format!("locked joint '{name}'"),
                format!("has a non-finite value {value}"),
            ));
        }
        locked_value.insert(j, *value);
    }
    Ok(Actuation {
        coordinate,
        locked_value,
    })
}

/// Joints in depth-first order from the root, children in file order.
fn depth_first_joints(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    link_index: &HashMap<&str, usize>,
) -> Vec<usize> {
    let mut order = Vec::with_capacity(robot.joints.len());
    let mut stack: Vec<usize> = tree.children[tree.root].iter().rev().copied().collect();
    while let Some(j) = stack.pop() {
        order.push(j);
        let child = link_index[robot.joints[j].child.link.as_str()];
        stack.extend(tree.children[child].iter().rev());
    }
    order
}

/// The most moving joints a model takes: the humanoids we know move 30 to 70 (the iCub with
/// its hands 53); parts of a model and of its data grow with the square of the count (the
/// support paths, the mass matrix: 1.8 GB for a chain of 20 000), so a file far beyond it is
/// refused before they are built.
pub const MAX_MOVING_JOINTS: usize = 1000;

/// Refuses `count` moving joints beyond [`MAX_MOVING_JOINTS`], naming the robot.
fn check_moving_joint_count(robot: &urdf_rs::Robot, count: usize) -> Result<()> {
    if count <= MAX_MOVING_JOINTS {
        return Ok(());
    }
    Err(Error::model(
        format!("robot '{}'", robot.name),
        format!("{count} moving joints, more than the {MAX_MOVING_JOINTS} a model takes"),
    ))
}

fn build(robot: &urdf_rs::Robot, options: &LoadOptions) -> Result<Model> {
    check_unique("link", robot.links.iter().map(|l| l.name.as_str()))?;
    check_unique("joint", robot.joints.iter().map(|j| j.name.as_str()))?;
    let link_index: HashMap<&str, usize> = robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect();
    let kinds = robot
        .joints
        .iter()
        .map(joint_kind)
        .collect::<Result<Vec<_>>>()?;
    let axes = robot
        .joints
        .iter()
        .map(joint_axis)
        .collect::<Result<Vec<_>>>()?;
    let mut warnings = Vec::new();
    let inertias = robot
        .links
        .iter()
        .map(|link| link_inertia(link, &mut warnings))
        .collect::<Result<Vec<_>>>()?;
    let tree = build_tree(robot, &link_index)?;
    let dfs = depth_first_joints(robot, &tree, &link_index);
    check_every_joint_reached(robot, &tree, &dfs)?;
    let actuation = resolve_actuation(robot, &kinds, &dfs, options)?;
    check_moving_joint_count(robot, actuation.coordinate.len())?;
    let walk = walk_bodies(robot, &link_index, &kinds, &axes, &dfs, &actuation);
    let (frames, body_inertias) =
        frames_and_inertias(robot, &tree, &link_index, &dfs, &inertias, &walk);
    let (body_of_coordinate, joint_names, support_paths) = coordinate_maps(&walk.joints);
    warnings.extend(massless_subtree_warnings(&walk.joints, &body_inertias));
    warnings.extend(robot.joints.iter().filter_map(inverted_limit_warning));
    let coordinates = robot
        .joints
        .iter()
        .filter(|j| joint_names.contains(&j.name));
    warnings.extend(coordinates.filter_map(mimic_warning));
    if let (true, Some(first)) = (options.strict, warnings.first()) {
        return Err(first.clone().into_error());
    }
    Ok(Model {
        support_paths,
        name: robot.name.clone(),
        joints: walk.joints,
        body_inertias,
        frames,
        gravity: Vector3::new(0.0, 0.0, -9.81),
        joint_names,
        body_of_coordinate,
        base_link: robot.links[tree.root].name.clone(),
        warnings,
    })
}

/// A joint that the depth-first walk did not reach closes a kinematic loop.
fn check_every_joint_reached(robot: &urdf_rs::Robot, tree: &Tree, dfs: &[usize]) -> Result<()> {
    if dfs.len() == robot.joints.len() {
        return Ok(());
    }
    let reached: std::collections::HashSet<usize> = dfs.iter().copied().collect();
    let j = (0..robot.joints.len())
        .find(|j| !reached.contains(j))
        .unwrap_or(0);
    Err(Error::model(
        format!("joint '{}'", robot.joints[j].name),
        format!(
            "kinematic loop: the joint (child link '{}') is not reachable from root link '{}'",
            robot.joints[j].child.link, robot.links[tree.root].name
        ),
    ))
}

/// The moving joints found by the walk, and where each link sits.
struct BodyWalk {
    /// Moving joints in body order (body `i + 1` is moved by `joints[i]`).
    joints: Vec<Joint>,
    /// Per URDF link: its body and `body_H_link`.
    link_body: Vec<(usize, Pose)>,
}

/// Walks the tree depth first: each moving joint starts a body; fixed and locked joints fold
/// their child link into the parent's body (a locked joint at its locked value).
fn walk_bodies(
    robot: &urdf_rs::Robot,
    link_index: &HashMap<&str, usize>,
    kinds: &[Option<JointKind>],
    axes: &[Vector3<f64>],
    dfs: &[usize],
    actuation: &Actuation,
) -> BodyWalk {
    let mut link_body = vec![(0usize, Pose::identity()); robot.links.len()];
    let mut joints = Vec::new();
    for &j in dfs {
        let urdf_joint = &robot.joints[j];
        let parent = link_index[urdf_joint.parent.link.as_str()];
        let child = link_index[urdf_joint.child.link.as_str()];
        let (parent_body, body_h_parent_link) = link_body[parent];
        let body_h_joint = body_h_parent_link.compose(&to_pose(&urdf_joint.origin));
        match (kinds[j], actuation.coordinate.get(&j)) {
            (Some(kind), Some(&coordinate)) => {
                joints.push(moving_joint(
                    urdf_joint,
                    kind,
                    parent_body,
                    coordinate,
                    body_h_joint,
                    axes[j],
                ));
                link_body[child] = (joints.len(), Pose::identity());
            }
            (kind, _) => {
                let motion = match kind {
                    Some(kind) => {
                        let value = actuation.locked_value.get(&j).copied().unwrap_or(0.0);
                        joint_motion(kind, &axes[j], value)
                    }
                    None => Pose::identity(),
                };
                link_body[child] = (parent_body, body_h_joint.compose(&motion));
            }
        }
    }
    BodyWalk { joints, link_body }
}

/// A revolute or prismatic joint whose `limit` has `lower > upper` is taken as unlimited, as
/// one with no limit (URDF's default, `lower = upper = 0`); unlike that default it is likely a
/// typo or swapped ends, so it is reported.
fn inverted_limit_warning(joint: &urdf_rs::Joint) -> Option<Warning> {
    use urdf_rs::JointType::{Prismatic, Revolute};
    let limit = &joint.limit;
    let limited = matches!(joint.joint_type, Revolute | Prismatic);
    (limited && limit.lower > limit.upper).then(|| {
        Warning::new(
            WarningKind::InvertedLimits,
            format!("joint '{}'", joint.name),
            format!(
                "limit lower {} is above upper {}: the joint is taken as unlimited",
                limit.lower, limit.upper
            ),
        )
    })
}

/// A moving joint that mimics another (`<mimic joint= multiplier= offset=>`) is a joint of its
/// own here: the coupling `q = multiplier q_other + offset` is not a constraint of the
/// dynamics, so the joint gets its own coordinate (and, in a scenario, its own actuator). Called
/// for the model's moving joints only: a fixed or locked joint's `mimic` changes nothing and is
/// not reported.
fn mimic_warning(joint: &urdf_rs::Joint) -> Option<Warning> {
    let mimic = joint.mimic.as_ref()?;
    Some(Warning::new(
        WarningKind::MimicNotModelled,
        format!("joint '{}'", joint.name),
        format!(
            "mimics joint '{}' (multiplier {}, offset {}): the coupling is not modelled, the \
             joint moves on its own",
            mimic.joint,
            mimic.multiplier.unwrap_or(1.0),
            mimic.offset.unwrap_or(0.0)
        ),
    ))
}

/// A moving joint with its limits (infinite where the URDF gives none).
fn moving_joint(
    urdf_joint: &urdf_rs::Joint,
    kind: JointKind,
    parent: usize,
    coordinate: usize,
    parent_h_joint: Pose,
    axis: Vector3<f64>,
) -> Joint {
    let limit = &urdf_joint.limit;
    let has_limits =
        urdf_joint.joint_type != urdf_rs::JointType::Continuous && limit.lower < limit.upper;
    Joint {
        name: urdf_joint.name.clone(),
        kind,
        parent,
        coordinate,
        parent_h_joint,
        axis,
        position_limits: if has_limits {
            [limit.lower, limit.upper]
        } else {
            [f64::NEG_INFINITY, f64::INFINITY]
        },
        effort_limit: if limit.effort > 0.0 {
            limit.effort
        } else {
            f64::INFINITY
        },
    }
}

/// Every link as a frame (tree order, root first, so listings read like the robot) and each
/// body's inertia, the merge of its links' inertias.
fn frames_and_inertias(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    link_index: &HashMap<&str, usize>,
    dfs: &[usize],
    inertias: &[Option<BodyInertia>],
    walk: &BodyWalk,
) -> (Vec<Frame>, Vec<BodyInertia>) {
    let mut body_inertias = vec![BodyInertia::zero(); walk.joints.len() + 1];
    let mut frames = Vec::with_capacity(robot.links.len());
    let mut ordered_links = vec![tree.root];
    ordered_links.extend(
        dfs.iter()
            .map(|j| link_index[robot.joints[*j].child.link.as_str()]),
    );
    for l in ordered_links {
        let (body, body_h_link) = walk.link_body[l];
        if let Some(inertia) = &inertias[l] {
            let in_body = inertia.transformed(&body_h_link);
            body_inertias[body] = body_inertias[body].merged(&in_body);
        }
        frames.push(Frame {
            name: robot.links[l].name.clone(),
            body,
            body_h_frame: body_h_link,
        });
    }
    (frames, body_inertias)
}

/// Per coordinate its body and joint name, and per body its support path (the moving bodies
/// from the base, excluded, down to the body itself).
fn coordinate_maps(joints: &[Joint]) -> (Vec<usize>, Vec<String>, Vec<Vec<usize>>) {
    let n = joints.len();
    let mut body_of_coordinate = vec![0; n];
    let mut joint_names = vec![String::new(); n];
    for (i, joint) in joints.iter().enumerate() {
        body_of_coordinate[joint.coordinate] = i + 1;
        joint_names[joint.coordinate] = joint.name.clone();
    }
    let mut support_paths: Vec<Vec<usize>> = vec![Vec::new()];
    for (k, joint) in joints.iter().enumerate() {
        let mut path = support_paths[joint.parent].clone();
        path.push(k + 1);
        support_paths.push(path);
    }
    (body_of_coordinate, joint_names, support_paths)
}

#[cfg(test)]
mod tests {
    use super::without_empty_textures;

    #[test]
    fn only_textures_without_a_file_are_removed() {
        let kept = r#"<texture filename="a.png"/><textures/><texturefoo/>"#;
        assert_eq!(without_empty_textures(kept), kept);
        assert_eq!(
            without_empty_textures("<m><texture/><texture >\n</texture></m>"),
            "<m>\n</m>"
        );
        assert_eq!(
            without_empty_textures("<m><texture  />x<texture filename='b'/></m>"),
            "<m>x<texture filename='b'/></m>"
        );
        // An unclosed texture is left for the parser to report.
        assert_eq!(without_empty_textures("<texture>"), "<texture>");
    }
}
