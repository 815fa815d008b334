//! `sea-sim init`: a two-feet balancing scenario for a robot the program has never seen, from
//! its URDF and its two contacts alone. The scenario carries its robot description inline
//! (`[robot.description]`): every joint a series elastic actuator scaled to the robot
//! ([`actuators`]), a standing posture found by inverse kinematics ([`posture`]), the foot
//! rectangle measured on the collision geometry ([`foot`], meshes read by [`crate::meshes`])
//! unless given, gains scaled to the robot ([`gains`]); the run is the paper's CoM sinusoid
//! (1 cm, 0.2 Hz, lateral) for 5 s, or with `walking` a walk ([`walking`]: the `[walking]`
//! defaults scaled to the robot, the controller settings the iCub walks with). The file is written beside its target and renamed over it only when
//! complete ([`crate::output::OutputFile`]).
//!
//! A robot whose two feet's 12 constraints are dependent at the standing posture (legs of 5
//! joints without a hip yaw, as `urdf/mini_biped.urdf`: rank 11, [`two_feet_rank`]) gets the
//! same scenario: the plant's unilateral contacts stand it, the controller restricts its QP to
//! the wrenches the joints can produce (`sea_ctrl::redundant_contacts`), and the scenario takes
//! a larger pseudo-inverse damping ([`write::REDUNDANT_PINV_DAMPING`], docs/findings/robots.md).

pub mod actuators;
pub mod foot;
pub mod gains;
pub mod mesh_files;
pub mod posture;
pub mod walking;
pub mod write;

use crate::error::{Error, Result};
use crate::scenario::robots::{add_contact_frames, ContactSpec, FootRectangle};
use nalgebra::DMatrix;
use sea_ctrl::redundant_contacts::RANK_TOLERANCE;
use sea_dyn::{Data, FrameId, LoadOptions, Model, PackageDirs};
use std::path::{Path, PathBuf};

/// What `sea-sim init` is given.
#[derive(Clone, Debug, Default)]
pub struct InitOptions {
    /// The URDF: a path or a `package://` / `file://` URI.
    pub urdf: String,
    /// The two contacts, left then right (the first is the stance sole the world is placed
    /// on): frame names or `LINK:x,y,z`.
    pub contacts: [String; 2],
    /// The foot rectangle (contact frame) of both feet; `None` measures it.
    pub foot: Option<FootRectangle>,
    /// Folders searched first for `package://` URIs.
    pub package_dirs: Vec<PathBuf>,
    /// The scenario file to write.
    pub out: PathBuf,
    /// The scenario's name (default: the robot's name and "two_feet", or "walk" with
    /// `walking`).
    pub name: Option<String>,
    /// Write a walking scenario ([`walking`]) instead of the CoM sinusoid.
    pub walking: bool,
    /// With `walking`: write the scaled settings without running the walk
    /// ([`walking::check_walk`]).
    pub skip_walk_check: bool,
}

/// What `init` found, for the user.
#[derive(Clone, Debug)]
pub struct InitReport {
    /// The file written.
    pub out: PathBuf,
    /// The robot's name, mass [kg] and number of joints.
    pub robot: (String, f64, usize),
    /// The foot rectangles used (left, right) and whether they were measured.
    pub feet: [FootRectangle; 2],
    /// Whether the rectangles were measured on the collision geometry.
    pub measured: bool,
    /// How far the base was lowered [m] and the posture's task error left.
    pub lowering_m: f64,
    /// The posture's largest task error [m or rad].
    pub residual: f64,
    /// How far the CoM stands from above the middle of the foot rectangles' centres [m]: 0,
    /// or the lateral offset legs without a hip yaw cannot reach ([`posture::standing_posture`]).
    pub com_offset_m: f64,
    /// The rank of the two feet's 12 constraints at the standing posture (12 with legs of 6
    /// joints; 11 with legs of 5, whose contact set is redundant: [`two_feet_rank`]).
    pub feet_rank: usize,
    /// The model's warnings (doubtful inertias, fused massless links), then the joints whose
    /// URDF effort is below the torque they hold standing ([`actuators::effort_warnings`]).
    pub warnings: Vec<String>,
    /// The robot's figures the walking settings scale with ([`walking::walking_figures`]).
    pub walking_figures: sea_ctrl::walking::RobotWalkingFigures,
    /// With `walking`, unless skipped: the runs of the written walk ([`walking::check_walk`]).
    pub walk_check: Option<walking::WalkCheck>,
}

/// Reads `FOOT` as `X0,X1,Y0,Y1` (metres, contact frame) with `x0 < x1` and `y0 < y1`.
pub fn parse_foot(text: &str) -> Result<FootRectangle> {
    let bad = || {
        Error::argument(
            "foot",
            "four finite numbers X0,X1,Y0,Y1 [m]",
            format!("'{text}'"),
        )
    };
    let values: Vec<f64> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    let [x0, x1, y0, y1] = values[..] else {
        return Err(bad());
    };
    check_foot(&FootRectangle {
        x: [x0, x1],
        y: [y0, y1],
    })
}

/// The farthest a foot rectangle's edge may lie from its contact frame [m]: a humanoid's sole
/// is tens of centimetres long; an edge beyond this is a unit or sign mistake.
pub const MAX_FOOT_EXTENT_M: f64 = 1.0;

/// `rectangle` when its minima are below its maxima and every edge lies within
/// [`MAX_FOOT_EXTENT_M`] of the contact frame.
pub fn check_foot(rectangle: &FootRectangle) -> Result<FootRectangle> {
    for (axis, [min, max]) in [("x", rectangle.x), ("y", rectangle.y)] {
        if min.abs() > MAX_FOOT_EXTENT_M || max.abs() > MAX_FOOT_EXTENT_M {
            return Err(Error::argument(
                "foot",
                format!("edges within {MAX_FOOT_EXTENT_M} m of the contact frame"),
                format!("{axis}0 = {min}, {axis}1 = {max}"),
            ));
        }
        // NaN compares to nothing: refused too.
        if min.partial_cmp(&max) != Some(std::cmp::Ordering::Less) {
            return Err(Error::argument(
                "foot",
                format!("{axis}0 < {axis}1 (contact frame) [m]"),
                format!("{axis}0 = {min}, {axis}1 = {max}"),
            ));
        }
    }
    Ok(*rectangle)
}

/// Writes the scenario of `options` and says what it found.
pub fn init(options: &InitOptions) -> Result<InitReport> {
    let never = std::sync::atomic::AtomicBool::new(false);
    Ok(init_unless_stopped(options, &never)?.expect("never stopped"))
}

/// The shortest distance between the two soles standing for `--walking` [m]: the steps' widths
/// scale with it, and soles that coincide (both hips on the body's plane) cannot alternate.
pub const MIN_WALKING_FEET_DISTANCE: f64 = 0.01;

/// [`init`], unless `stop` is raised before the scenario is written (checked after reading
/// the URDF, after building the model, before the standing posture and before writing): then
/// nothing is written and the result is `None` (a stop signal while a large robot loads).
/// With `walking` the written walk is then run ([`walking::check_walk`]; `stop` ends the run
/// under way and leaves the walk written at the standing CoM height, the report saying so).
pub fn init_unless_stopped(
    options: &InitOptions,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<Option<InitReport>> {
    let stopped = || stop.load(std::sync::atomic::Ordering::SeqCst);
    let dirs = PackageDirs::from_environment(options.package_dirs.iter().cloned());
    let urdf_file = resolve_urdf(&options.urdf, &dirs)?;
    crate::output::check_distinct(
        &[("the URDF", &urdf_file)],
        &[("the scenario written", &options.out)],
    )?;
    let text = sea_dyn::files::read_text(&urdf_file).map_err(|e| Error::io(&urdf_file, e))?;
    if stopped() {
        return Ok(None);
    }
    let mut model = Model::from_urdf_str(&text, &LoadOptions::default())
        .map_err(|e| Error::from(e.in_file(&urdf_file)))?;
    if stopped() {
        return Ok(None);
    }
    for contact in &options.contacts {
        ContactSpec::parse(contact)?;
    }
    add_contact_frames(&mut model, &options.contacts)?;
    let feet = options
        .contacts
        .clone()
        .map(|name| model.frame_id(&name).expect("added above"));
    one_contact_per_leg(&model, feet, &options.contacts)?;
    let urdf_dir = urdf_file.parent().unwrap_or(Path::new("."));
    let meshes = mesh_files::check_mesh_files(&text, urdf_dir, &dirs)?;
    let inputs: Vec<(&str, &Path)> = meshes
        .iter()
        .map(|(role, file)| (role.as_str(), file.as_path()))
        .collect();
    crate::output::check_distinct(&inputs, &[("the scenario written", &options.out)])?;
    let (rectangles, measured) = feet_rectangles(options, &model, feet, &text, urdf_dir, &dirs)?;
    if stopped() {
        return Ok(None);
    }
    let standing = posture::standing_posture(&model, feet, rectangles)?;
    let standing_torques = actuators::standing_torques(&model, feet, &standing);
    let feet_rank = two_feet_rank(&model, feet, &standing);
    let walking_figures = walking::walking_figures(&model, feet, &standing);
    if options.walking
        && (walking_figures.feet_distance.is_nan()
            || walking_figures.feet_distance < MIN_WALKING_FEET_DISTANCE)
    {
        return Err(Error::argument(
            "--contacts",
            format!("two soles at least {MIN_WALKING_FEET_DISTANCE} m apart standing, to walk on"),
            format!(
                "'{}' and '{}' {:.4} m apart",
                options.contacts[0], options.contacts[1], walking_figures.feet_distance
            ),
        ));
    }
    let settings = options
        .walking
        .then(|| walking::walking_settings(&walking_figures))
        .transpose()?;
    let body = write::Body {
        rectangles,
        standing: &standing,
        standing_torques: &standing_torques,
        feet_rank,
        walking: settings.as_ref(),
    };
    if stopped() {
        return Ok(None);
    }
    let (written, walk_check) = write_and_check(options, &model, &body, stop)?;
    Ok(Some(InitReport {
        out: written,
        robot: (model.name.clone(), model.total_mass(), model.n_joints()),
        feet: rectangles,
        measured,
        lowering_m: standing.lowering_m,
        residual: standing.residual,
        com_offset_m: standing.com_offset_m,
        feet_rank,
        warnings: (model.warnings.iter().map(|w| w.to_string()))
            .chain(actuators::effort_warnings(&model, &standing_torques))
            .collect(),
        walking_figures,
        walk_check,
    }))
}

/// Writes the scenario of `body` and, for a walk unless `options.skip_walk_check`, runs it
/// ([`walking::check_walk`], rewriting the file at each lower height). A walk written to
/// something other than a regular file (a device, a pipe, a link to one) is not checked: it
/// cannot be read back or written again.
fn write_and_check(
    options: &InitOptions,
    model: &Model,
    body: &write::Body<'_>,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<(PathBuf, Option<walking::WalkCheck>)> {
    let written = write::write_scenario(options, model, body)?;
    let regular = std::fs::symlink_metadata(&written).is_ok_and(|m| m.file_type().is_file());
    let Some(walk) = body.walking.filter(|_| !options.skip_walk_check && regular) else {
        return Ok((written, None));
    };
    let mut settings = walk.clone();
    let rewrite = |settings: &sea_ctrl::walking::WalkingSettings| {
        let body = write::Body {
            walking: Some(settings),
            ..*body
        };
        write::write_scenario(options, model, &body).map(|_| ())
    };
    let check = walking::check_walk(&written, &mut settings, rewrite, stop)?;
    Ok((written, Some(check)))
}

/// The two soles' rectangles, in the order of `options.contacts`, and whether they were
/// measured: `--foot` for both when given, else each measured from its foot's collision
/// geometry (`foot::foot_rectangle`).
fn feet_rectangles(
    options: &InitOptions,
    model: &Model,
    feet: [FrameId; 2],
    urdf_text: &str,
    urdf_dir: &Path,
    dirs: &PackageDirs,
) -> Result<([FootRectangle; 2], bool)> {
    if let Some(foot) = &options.foot {
        return Ok(([check_foot(foot)?; 2], false));
    }
    let measure = |k: usize| {
        foot::foot_rectangle(
            model,
            feet[k],
            urdf_text,
            urdf_dir,
            dirs,
            &options.contacts[k],
        )
        .map(|(rectangle, _)| rectangle)
    };
    Ok(([measure(0)?, measure(1)?], true))
}

/// The rank of the two feet's stacked 12 x nv contact Jacobian at the standing posture. A leg
/// of 6 joints (hip yaw, roll, pitch, knee, ankle pitch, roll) moves its foot in all 6
/// directions: rank 12. Two legs of 5 joints lacking the same motion (a hip yaw) leave a
/// relative motion of the feet (their relative yaw) that nothing produces: rank 11, the contact
/// set is redundant. The plant's unilateral contacts stand it; the controller restricts its QP
/// to the wrenches the joints can produce (`sea_ctrl::redundant_contacts`), and the scenario
/// then takes [`write::REDUNDANT_PINV_DAMPING`] (docs/findings/robots.md).
pub fn two_feet_rank(model: &Model, feet: [FrameId; 2], standing: &posture::Standing) -> usize {
    let mut q = model.neutral();
    q[7..].copy_from_slice(&standing.joints);
    let mut data = Data::new(model);
    let mut stacked = DMatrix::zeros(12, model.nv());
    for (k, &foot) in feet.iter().enumerate() {
        let jacobian = sea_dyn::frame_jacobian(model, &mut data, &q, foot);
        stacked.rows_mut(6 * k, 6).copy_from(jacobian);
    }
    let singular = stacked.singular_values();
    let largest = singular.max();
    singular
        .iter()
        .filter(|&&s| s > RANK_TOLERANCE * largest)
        .count()
}

/// The URDF file of `urdf` (a path or a URI); an error names the argument.
fn resolve_urdf(urdf: &str, dirs: &PackageDirs) -> Result<PathBuf> {
    dirs.resolve(urdf, Path::new(".")).map_err(|e| {
        Error::argument(
            "urdf",
            format!("a URDF that can be found ({e})"),
            format!("'{urdf}'"),
        )
    })
}

/// Two contacts on two different legs: the first bodies below the base on their support paths
/// differ (otherwise one leg, or one foot, carries both and the robot cannot stand).
fn one_contact_per_leg(model: &Model, feet: [FrameId; 2], names: &[String; 2]) -> Result<()> {
    let leg = |frame: FrameId| {
        model
            .support_path(model.frames[frame].body)
            .first()
            .copied()
    };
    match (leg(feet[0]), leg(feet[1])) {
        (Some(left), Some(right)) if left != right => Ok(()),
        _ => Err(Error::invalid(
            "robot.contacts",
            "the robot cannot stand: the two contacts must be on two different legs (these \
             hang from the same link below the base, or on the base itself)",
            format!("'{}', '{}'", names[0], names[1]),
        )),
    }
}
