//! The channels of a run and the encoding of one [`Sample`] into their messages, shared by
//! the MCAP log and the live server.

use super::json_schemas::{
    BASE_POSE_SCHEMA, COM_SCHEMA, CONTACT_CHECK_SCHEMA, CONTACT_POINTS_SCHEMA,
    CONTACT_WRENCHES_SCHEMA, DISTURBANCES_SCHEMA, JOINT_STATE_SCHEMA, MOMENTUM_SCHEMA,
    MOTOR_STATE_SCHEMA, QP_STATUS_SCHEMA,
};
use super::scene::{ContactPoints, ForceArrows, Markers, StaticScene};
use super::walking::WalkingScene;
use super::{FootRectangle, WORLD_FRAME};
use crate::error::Error;
use crate::Result;
use ::foxglove::messages::{
    FrameTransform, FrameTransforms, Quaternion, SceneUpdate, Timestamp, Vector3,
};
use ::foxglove::{Encode, Schema};
use sea_ctrl::qp::QpStatus;
use sea_ctrl::walking::Gait;
use sea_dyn::spatial::quaternion_from_rotation;
use sea_dyn::{Data, Model};
use sea_loop::{ContactConstraint, Sample, WrenchCheck};
use serde::Serialize;

/// A channel of the log (see the module documentation of [`crate::foxglove`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Topic {
    /// `/tf`: `foxglove.FrameTransforms`, `world_H_link` of every link.
    Tf,
    /// `/scene`: `foxglove.SceneUpdate`, robot bodies, support polygon, CoM, wrenches.
    Scene,
    /// `/com`: `sea_momentum.Com`.
    Com,
    /// `/momentum`: `sea_momentum.Momentum`.
    Momentum,
    /// `/joints`: `sea_momentum.JointState`.
    Joints,
    /// `/motors`: `sea_momentum.MotorState`.
    Motors,
    /// `/contact_wrenches`: `sea_momentum.ContactWrenches`.
    ContactWrenches,
    /// `/qp`: `sea_momentum.QpStatus`.
    Qp,
    /// `/base`: `sea_momentum.BasePose`.
    Base,
    /// `/disturbances`: `sea_momentum.Disturbances`.
    Disturbances,
    /// `/planned_wrenches`: `sea_momentum.ContactWrenches`, the QP's planned wrenches.
    PlannedWrenches,
    /// `/contact_points`: `sea_momentum.ContactPoints`, only under unilateral contacts (not
    /// in [`Topic::ALL`]; see [`SampleEncoder::set_contact_points`]).
    ContactPoints,
    /// `/contact_check`: `sea_momentum.ContactCheck`, only under unilateral contacts, at the
    /// samples where the contact check ran (not in [`Topic::ALL`]; see
    /// [`SampleEncoder::encode`]).
    ContactCheck,
}

/// Encoding of our own channels' messages and of their schemas.
const JSON: (&str, &str) = ("json", "jsonschema");

impl Topic {
    /// Every channel of every run, in the order they are registered.
    pub const ALL: [Topic; 11] = [
        Topic::Tf,
        Topic::Scene,
        Topic::Com,
        Topic::Momentum,
        Topic::Joints,
        Topic::Motors,
        Topic::ContactWrenches,
        Topic::Qp,
        Topic::Base,
        Topic::Disturbances,
        Topic::PlannedWrenches,
    ];

    /// Position in [`Self::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The topic name, e.g. `/tf`.
    pub fn name(self) -> &'static str {
        match self {
            Topic::Tf => "/tf",
            Topic::Scene => "/scene",
            Topic::Com => "/com",
            Topic::Momentum => "/momentum",
            Topic::Joints => "/joints",
            Topic::Motors => "/motors",
            Topic::ContactWrenches => "/contact_wrenches",
            Topic::Qp => "/qp",
            Topic::Base => "/base",
            Topic::Disturbances => "/disturbances",
            Topic::PlannedWrenches => "/planned_wrenches",
            Topic::ContactPoints => "/contact_points",
            Topic::ContactCheck => "/contact_check",
        }
    }

    /// Message encoding: `protobuf` for the SDK's types, `json` for ours.
    pub fn message_encoding(self) -> String {
        match self {
            Topic::Tf => FrameTransforms::get_message_encoding(),
            Topic::Scene => SceneUpdate::get_message_encoding(),
            _ => JSON.0.to_string(),
        }
    }

    /// The schema: the SDK's protobuf descriptor for its types, our JSON Schema otherwise.
    pub fn schema(self) -> Schema {
        let json = |name: &str, text: &'static str| Schema::new(name, JSON.1, text.as_bytes());
        match self {
            Topic::Tf => FrameTransforms::get_schema().expect("the SDK gives its schemas"),
            Topic::Scene => SceneUpdate::get_schema().expect("the SDK gives its schemas"),
            Topic::Com => json("sea_momentum.Com", COM_SCHEMA),
            Topic::Momentum => json("sea_momentum.Momentum", MOMENTUM_SCHEMA),
            Topic::Joints => json("sea_momentum.JointState", JOINT_STATE_SCHEMA),
            Topic::Motors => json("sea_momentum.MotorState", MOTOR_STATE_SCHEMA),
            Topic::ContactWrenches | Topic::PlannedWrenches => {
                json("sea_momentum.ContactWrenches", CONTACT_WRENCHES_SCHEMA)
            }
            Topic::Qp => json("sea_momentum.QpStatus", QP_STATUS_SCHEMA),
            Topic::Base => json("sea_momentum.BasePose", BASE_POSE_SCHEMA),
            Topic::Disturbances => json("sea_momentum.Disturbances", DISTURBANCES_SCHEMA),
            Topic::ContactPoints => json("sea_momentum.ContactPoints", CONTACT_POINTS_SCHEMA),
            Topic::ContactCheck => json("sea_momentum.ContactCheck", CONTACT_CHECK_SCHEMA),
        }
    }
}

// ---- Bodies of our JSON messages (borrowing, so a sample allocates little). ----

#[derive(Serialize)]
struct ComMsg {
    com: [f64; 3],
    reference: [f64; 3],
    error: [f64; 3],
}

#[derive(Serialize)]
struct MomentumMsg<'a> {
    linear: &'a [f64],
    angular: &'a [f64],
    external_wrench: &'a [f64],
}

#[derive(Serialize)]
struct JointStateMsg<'a> {
    names: &'a [String],
    position: &'a [f64],
    velocity: &'a [f64],
    torque: &'a [f64],
}

#[derive(Serialize)]
struct MotorStateMsg<'a> {
    names: &'a [String],
    position: &'a [f64],
    velocity: &'a [f64],
    velocity_desired: &'a [f64],
    torque: &'a [f64],
}

#[derive(Serialize)]
struct ContactMsg<'a> {
    frame: &'a str,
    force: &'a [f64],
    moment: &'a [f64],
}

#[derive(Serialize)]
struct ContactWrenchesMsg<'a> {
    contacts: Vec<ContactMsg<'a>>,
}

#[derive(Serialize)]
struct DisturbanceMsg<'a> {
    link: &'a str,
    active: bool,
    force: &'a [f64],
    torque: &'a [f64],
}

#[derive(Serialize)]
struct DisturbancesMsg<'a> {
    disturbances: Vec<DisturbanceMsg<'a>>,
}

#[derive(Serialize)]
struct ContactPointMsg<'a> {
    contact: &'a str,
    index: usize,
    active: bool,
    position: &'a [f64],
    force: &'a [f64],
}

#[derive(Serialize)]
struct ContactPointsMsg<'a> {
    points: Vec<ContactPointMsg<'a>>,
}

#[derive(Serialize)]
struct CheckMsg {
    constraint: &'static str,
    value: f64,
    lower: Option<f64>,
    upper: Option<f64>,
    violated: bool,
}

#[derive(Serialize)]
struct FootCheckMsg<'a> {
    contact: &'a str,
    violated: Option<&'static str>,
    checks: [CheckMsg; 4],
}

#[derive(Serialize)]
struct ContactCheckMsg<'a> {
    contacts: Vec<FootCheckMsg<'a>>,
}

/// One foot's [`WrenchCheck`] as its `/contact_check` entry.
fn foot_check_msg<'a>(contact: &'a str, check: &WrenchCheck) -> FootCheckMsg<'a> {
    let center_of_pressure = |k: usize, constraint, [lower, upper]: [f64; 2]| CheckMsg {
        constraint,
        value: check.center_of_pressure[k],
        lower: Some(lower),
        upper: Some(upper),
        violated: check.center_of_pressure_beyond(k).is_some(),
    };
    FootCheckMsg {
        contact,
        violated: check.violated.as_ref().map(ContactConstraint::kind),
        checks: [
            CheckMsg {
                constraint: "normal_force",
                value: check.normal_force,
                lower: Some(0.0),
                upper: None,
                violated: check.normal_force_violated(),
            },
            CheckMsg {
                constraint: "friction",
                value: check.friction_ratio,
                lower: None,
                upper: Some(check.friction),
                violated: check.friction_violated(),
            },
            center_of_pressure(0, "center_of_pressure_x", check.foot_x),
            center_of_pressure(1, "center_of_pressure_y", check.foot_y),
        ],
    }
}

#[derive(Serialize)]
struct QpStatusMsg<'a> {
    status: &'a str,
    failures: usize,
}

#[derive(Serialize)]
struct BasePoseMsg<'a> {
    position: &'a [f64],
    orientation_wxyz: &'a [f64],
    linear_velocity: &'a [f64],
    angular_velocity: &'a [f64],
}

/// Encodes [`Sample`]s into the messages of every [`Topic`]. Holds the model (for the link
/// poses of `/tf` and the sole positions of the wrench arrows) and reuses its messages and
/// buffer between samples.
pub struct SampleEncoder {
    model: Model,
    data: Data,
    elastic_joint_names: Vec<String>,
    /// Contact names, extended by `contact_<k>` for contacts beyond the given names.
    contact_labels: Vec<String>,
    /// Frame of each named contact (`None`: not a model frame, no arrow origin).
    contact_frames: Vec<Option<usize>>,
    /// Origins of the contact frames in the current sample (world) [m].
    contact_origins: Vec<[f64; 3]>,
    /// The link of each disturbance, extended by `disturbance_<k>` beyond the given links.
    disturbance_links: Vec<String>,
    /// Frame of each given disturbance link (`None`: not a model frame, no arrow).
    disturbance_frames: Vec<Option<usize>>,
    /// Origins of the disturbance links in the current sample (world) [m].
    disturbance_origins: Vec<[f64; 3]>,
    /// Unilateral contacts: each contact point's contact label index and index in its foot
    /// (empty: no `/contact_points`).
    contact_points: Vec<(usize, usize)>,
    /// `/tf`, child frame names filled once.
    tf: FrameTransforms,
    /// The static part of `/scene`, once set.
    scene: Option<StaticScene>,
    markers: Markers,
    /// `[walking]`: the walk's markers and events, once set.
    walking: Option<WalkingScene>,
    buffer: Vec<u8>,
    /// The text of the sample's QP status ([`write_qp_status`]).
    qp_text: String,
}

impl SampleEncoder {
    /// An encoder for `model`; `elastic_joint_names` labels theta entries, `contact_names` the
    /// wrenches (contacts beyond the names are called `contact_<k>`).
    pub fn new(model: &Model, elastic_joint_names: &[String], contact_names: &[String]) -> Self {
        let tf = FrameTransforms {
            transforms: model
                .frames
                .iter()
                .map(|frame| FrameTransform {
                    parent_frame_id: WORLD_FRAME.to_string(),
                    child_frame_id: frame.name.clone(),
                    ..Default::default()
                })
                .collect(),
        };
        Self {
            model: model.clone(),
            data: Data::new(model),
            elastic_joint_names: elastic_joint_names.to_vec(),
            contact_labels: contact_names.to_vec(),
            contact_frames: contact_names
                .iter()
                .map(|c| model.frame_id(c).ok())
                .collect(),
            contact_origins: Vec::with_capacity(contact_names.len()),
            disturbance_links: Vec::new(),
            disturbance_frames: Vec::new(),
            disturbance_origins: Vec::new(),
            contact_points: Vec::new(),
            tf,
            scene: None,
            markers: Markers::new(contact_names),
            walking: None,
            buffer: Vec::with_capacity(8192),
            qp_text: String::new(),
        }
    }

    /// Adds the robot's bodies and support polygon to `/scene`.
    pub(crate) fn set_scene(&mut self, scene: StaticScene) {
        self.scene = Some(scene);
    }

    /// Names the disturbances of `/disturbances` by their links (`[[disturbances]]` order);
    /// unnamed ones are `disturbance_<k>`. Each link of the model gets a push arrow in
    /// `/scene`.
    pub fn set_disturbance_links(&mut self, links: &[String]) {
        self.disturbance_links = links.to_vec();
        self.disturbance_frames = links.iter().map(|l| self.model.frame_id(l).ok()).collect();
        self.disturbance_origins = vec![[0.0; 3]; links.len()];
        self.markers.set_pushes(links);
    }

    /// Unilateral contacts: `counts[c]` points on contact `c`, drawn in `/scene` and sent on
    /// `/contact_points` (the samples' contact points, in order). Empty (bilateral contacts,
    /// the default): neither.
    pub fn set_contact_points(&mut self, counts: &[usize]) {
        self.contact_points.clear();
        for (c, &count) in counts.iter().enumerate() {
            while self.contact_labels.len() <= c {
                let k = self.contact_labels.len();
                self.contact_labels.push(format!("contact_{k}"));
            }
            self.contact_points.extend((0..count).map(|i| (c, i)));
        }
        self.markers.set_contact_points(self.contact_points.len());
    }

    /// `[walking]`: draws the walk `gait` in `/scene` (footsteps with the soles `foot`, none
    /// when `None`; the swing path; the planned and measured DCM, the planned VRP and CoM;
    /// module `walking` of [`crate::foxglove`]) and gives its events
    /// ([`Self::walking_events`]; measured lift-offs from the contact points of
    /// [`Self::set_contact_points`], so call that first).
    pub fn set_walking(&mut self, gait: &Gait, foot: Option<FootRectangle>) {
        let mut counts = vec![0; self.contact_labels.len()];
        for &(c, _) in &self.contact_points {
            counts[c] += 1;
        }
        let mass = self.model.total_mass();
        let contacts = (&self.contact_labels[..], &counts[..]);
        self.walking = Some(WalkingScene::new(gait, mass, foot, contacts));
    }

    /// `[walking]`: draws `gait`, the walk as the controller changed it, from the next sample
    /// on (its footsteps, swing paths, DCM path and the planned events still to come); nothing
    /// when no walk was set.
    pub fn set_gait(&mut self, gait: Gait) {
        if let Some(walking) = self.walking.as_mut() {
            walking.set_gait(gait);
        }
    }

    /// `[walking]`: the `/events` messages due at `sample` (time [ns], encoded `foxglove.Log`):
    /// the planned lift-offs and touchdowns up to its time, and the feet that stopped
    /// carrying force since the last sample; none when not walking.
    ///
    /// Errors: [`Error::Log`] when a message does not encode.
    pub fn walking_events(&mut self, sample: &Sample<'_>) -> Result<Vec<(u64, Vec<u8>)>> {
        match self.walking.as_mut() {
            Some(walking) => walking.events(sample),
            None => Ok(Vec::new()),
        }
    }

    /// Whether the samples' contact points are encoded (`/contact_points` is sent).
    pub fn has_contact_points(&self) -> bool {
        !self.contact_points.is_empty()
    }

    /// The link frames (the child frames of `/tf`).
    pub fn link_frames(&self) -> Vec<String> {
        self.model.frames.iter().map(|f| f.name.clone()).collect()
    }

    /// The contact names given at creation.
    pub fn contact_names(&self) -> &[String] {
        &self.contact_labels[..self.contact_frames.len()]
    }

    /// Checks the sizes of the state (against its layout), `q`, `nu` and the wrenches.
    ///
    /// Errors: [`Error::Log`] naming the wrong size.
    pub fn check(&self, sample: &Sample<'_>) -> Result<()> {
        let nx = sample.layout.nx();
        if sample.state.len() != nx {
            return Err(Error::Log(format!(
                "the state has {} entries, its layout needs nx = {nx}",
                sample.state.len()
            )));
        }
        let (nq, nv) = (self.model.nq(), self.model.nv());
        if sample.q().len() != nq {
            return Err(Error::Log(format!(
                "q has {} entries, the model needs nq = {nq}",
                sample.q().len()
            )));
        }
        if sample.nu().len() != nv {
            return Err(Error::Log(format!(
                "nu has {} entries, the model needs nv = {nv}",
                sample.nu().len()
            )));
        }
        for (name, wrenches) in [
            ("contact_wrenches", sample.contact_wrenches),
            ("planned_wrenches", sample.planned_wrenches),
        ] {
            if wrenches.len() % 6 != 0 {
                return Err(Error::Log(format!(
                    "{name} has {} entries, not a multiple of 6",
                    wrenches.len()
                )));
            }
        }
        Ok(())
    }

    /// Encodes `sample` and hands each message to `emit(topic, time_ns, bytes)`, in the order
    /// of [`Topic::ALL`], then `/contact_points` when set
    /// ([`SampleEncoder::set_contact_points`]), then `/contact_check` when the sample has
    /// the contact check (unilateral contacts). `/tf` and `/scene` are skipped when a pose is
    /// not finite.
    ///
    /// Errors: those of [`Self::check`] and of `emit`.
    pub fn encode(
        &mut self,
        sample: &Sample<'_>,
        mut emit: impl FnMut(Topic, u64, &[u8]) -> Result<()>,
    ) -> Result<()> {
        self.check(sample)?;
        let time = nanoseconds(sample.time_s);
        if self.encode_tf(time, sample.q()) {
            emit(Topic::Tf, time, &self.buffer)?;
        }
        if self.encode_scene(time, sample) {
            emit(Topic::Scene, time, &self.buffer)?;
        }
        for topic in &Topic::ALL[2..] {
            self.buffer.clear();
            self.encode_json(*topic, sample)?;
            emit(*topic, time, &self.buffer)?;
        }
        if self.has_contact_points() {
            self.buffer.clear();
            self.encode_json(Topic::ContactPoints, sample)?;
            emit(Topic::ContactPoints, time, &self.buffer)?;
        }
        if !sample.contact_checks.is_empty() {
            self.buffer.clear();
            self.encode_json(Topic::ContactCheck, sample)?;
            emit(Topic::ContactCheck, time, &self.buffer)?;
        }
        Ok(())
    }

    /// `/tf` into the buffer: `world_H_link` of every frame (also updates the contact
    /// origins); `false` when a pose is not finite.
    fn encode_tf(&mut self, time: u64, q: &[f64]) -> bool {
        sea_dyn::forward_kinematics(&self.model, &mut self.data, q);
        let stamp = time_stamp(time);
        let mut finite = true;
        for (id, transform) in self.tf.transforms.iter_mut().enumerate() {
            let pose = sea_dyn::frame_placement(&self.model, &self.data, id);
            let [w, x, y, z] = quaternion_from_rotation(&pose.rotation);
            let t = pose.translation;
            finite &= t.iter().chain([w, x, y, z].iter()).all(|v| v.is_finite());
            transform.timestamp = Some(stamp);
            transform.translation = Some(Vector3 {
                x: t.x,
                y: t.y,
                z: t.z,
            });
            transform.rotation = Some(Quaternion { x, y, z, w });
        }
        self.contact_origins.clear();
        for frame in &self.contact_frames {
            let origin = frame.map_or([f64::NAN; 3], |id| {
                let t = sea_dyn::frame_placement(&self.model, &self.data, id).translation;
                [t.x, t.y, t.z]
            });
            self.contact_origins.push(origin);
        }
        let pushed = self.disturbance_frames.iter();
        for (origin, frame) in self.disturbance_origins.iter_mut().zip(pushed) {
            // A link that is not a model frame keeps its arrow at the world origin (the
            // scenario check refuses such links before a run).
            if let Some(id) = *frame {
                let t = sea_dyn::frame_placement(&self.model, &self.data, id).translation;
                *origin = [t.x, t.y, t.z];
            }
        }
        self.buffer.clear();
        finite && self.tf.encode(&mut self.buffer).is_ok()
    }

    /// `/scene` into the buffer: the static part, then the markers; `false` when a marker is
    /// not finite.
    fn encode_scene(&mut self, time: u64, sample: &Sample<'_>) -> bool {
        self.buffer.clear();
        if let Some(scene) = &self.scene {
            self.buffer.extend_from_slice(&scene.encoded);
        }
        let contacts = ForceArrows {
            wrenches: sample.contact_wrenches,
            points: &self.contact_origins,
        };
        let pushes = ForceArrows {
            wrenches: sample.disturbance_wrenches,
            points: &self.disturbance_origins,
        };
        let points = ContactPoints {
            positions: sample.contact_point_positions,
            forces: sample.contact_point_forces,
            active: sample.contact_point_active,
        };
        let stamp = time_stamp(time);
        self.markers.encode(
            stamp,
            [sample.com, sample.com_reference],
            (contacts, pushes, points),
            &mut self.buffer,
        ) && self
            .walking
            .as_mut()
            .is_none_or(|walking| walking.encode(stamp, sample, &mut self.buffer))
    }

    /// One of our JSON channels into the buffer.
    fn encode_json(&mut self, topic: Topic, sample: &Sample<'_>) -> Result<()> {
        let buffer = &mut self.buffer;
        let result = match topic {
            Topic::Com => serde_json::to_writer(
                buffer,
                &ComMsg {
                    com: sample.com,
                    reference: sample.com_reference,
                    error: [0, 1, 2].map(|k| sample.com[k] - sample.com_reference[k]),
                },
            ),
            Topic::Momentum => serde_json::to_writer(
                buffer,
                &MomentumMsg {
                    linear: &sample.momentum[..3],
                    angular: &sample.momentum[3..],
                    external_wrench: &sample.external_wrench,
                },
            ),
            Topic::Joints => serde_json::to_writer(
                buffer,
                &JointStateMsg {
                    names: &self.model.joint_names,
                    position: &sample.q()[7..],
                    velocity: &sample.nu()[6..],
                    torque: sample.joint_torques,
                },
            ),
            Topic::Motors => serde_json::to_writer(
                buffer,
                &MotorStateMsg {
                    names: &self.elastic_joint_names,
                    position: sample.theta(),
                    velocity: sample.thetadot(),
                    velocity_desired: sample.thetadot_desired,
                    torque: sample.motor_torques,
                },
            ),
            Topic::ContactWrenches | Topic::PlannedWrenches => {
                let wrenches = match topic {
                    Topic::ContactWrenches => sample.contact_wrenches,
                    _ => sample.planned_wrenches,
                };
                while self.contact_labels.len() < wrenches.len() / 6 {
                    let k = self.contact_labels.len();
                    self.contact_labels.push(format!("contact_{k}"));
                }
                let contacts = wrenches
                    .chunks_exact(6)
                    .zip(&self.contact_labels)
                    .map(|(w, frame)| ContactMsg {
                        frame,
                        force: &w[..3],
                        moment: &w[3..],
                    })
                    .collect();
                serde_json::to_writer(buffer, &ContactWrenchesMsg { contacts })
            }
            Topic::Qp => {
                write_qp_status(sample.qp_status, &mut self.qp_text);
                serde_json::to_writer(
                    buffer,
                    &QpStatusMsg {
                        status: &self.qp_text,
                        failures: sample.qp_failures,
                    },
                )
            }
            Topic::Base => serde_json::to_writer(
                buffer,
                &BasePoseMsg {
                    position: &sample.q()[..3],
                    orientation_wxyz: &sample.q()[3..7],
                    linear_velocity: &sample.nu()[..3],
                    angular_velocity: &sample.nu()[3..6],
                },
            ),
            Topic::Disturbances => {
                let wrenches = sample.disturbance_wrenches;
                while self.disturbance_links.len() < wrenches.len() / 6 {
                    let k = self.disturbance_links.len();
                    self.disturbance_links.push(format!("disturbance_{k}"));
                }
                let disturbances = wrenches
                    .chunks_exact(6)
                    .zip(&self.disturbance_links)
                    .map(|(w, link)| DisturbanceMsg {
                        link,
                        active: w.iter().any(|&v| v != 0.0),
                        force: &w[..3],
                        torque: &w[3..],
                    })
                    .collect();
                serde_json::to_writer(buffer, &DisturbancesMsg { disturbances })
            }
            Topic::ContactPoints => {
                let labels = &self.contact_labels;
                let values = sample.contact_point_positions.chunks_exact(3);
                let values = values.zip(sample.contact_point_forces.chunks_exact(3));
                let points = self
                    .contact_points
                    .iter()
                    .zip(values)
                    .enumerate()
                    .map(|(k, (&(c, index), (position, force)))| ContactPointMsg {
                        contact: &labels[c],
                        index,
                        active: sample.contact_point_active.get(k).copied().unwrap_or(false),
                        position,
                        force,
                    })
                    .collect();
                serde_json::to_writer(buffer, &ContactPointsMsg { points })
            }
            Topic::ContactCheck => {
                let checks = sample.contact_checks;
                while self.contact_labels.len() < checks.len() {
                    let k = self.contact_labels.len();
                    self.contact_labels.push(format!("contact_{k}"));
                }
                let contacts = checks
                    .iter()
                    .zip(&self.contact_labels)
                    .map(|(check, contact)| foot_check_msg(contact, check))
                    .collect();
                serde_json::to_writer(buffer, &ContactCheckMsg { contacts })
            }
            Topic::Tf | Topic::Scene => unreachable!("protobuf channels"),
        };
        result.map_err(|e| Error::Log(format!("{}: {e}", topic.name())))
    }
}

/// The logged text of a QP status, `"solved"`, `"momentum_relaxed"` or `"fallback: <reason>"`,
/// into `text` (cleared
/// first; no allocation once `text` is large enough).
fn write_qp_status(status: &QpStatus, text: &mut String) {
    text.clear();
    match status {
        QpStatus::Solved => text.push_str("solved"),
        QpStatus::MomentumRelaxed => text.push_str("momentum_relaxed"),
        QpStatus::Fallback(reason) => {
            text.push_str("fallback: ");
            text.push_str(reason);
        }
    }
}

/// Time in seconds to nanoseconds; negative or NaN times clamp to 0, huge ones saturate.
pub fn nanoseconds(time_s: f64) -> u64 {
    if time_s.is_nan() || time_s <= 0.0 {
        0
    } else {
        (time_s * 1e9).round() as u64
    }
}

/// A `foxglove` time stamp of `time` nanoseconds (saturating past 2106).
fn time_stamp(time: u64) -> Timestamp {
    let sec = u32::try_from(time / 1_000_000_000).unwrap_or(u32::MAX);
    Timestamp::new(sec, (time % 1_000_000_000) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_conversion() {
        assert_eq!(nanoseconds(0.0), 0);
        assert_eq!(nanoseconds(-1.0), 0);
        assert_eq!(nanoseconds(f64::NAN), 0);
        assert_eq!(nanoseconds(1.5), 1_500_000_000);
        assert_eq!(nanoseconds(0.001), 1_000_000);
        assert_eq!(time_stamp(1_500_000_000), Timestamp::new(1, 500_000_000));
    }

    #[test]
    fn each_topics_index_is_its_place_in_all() {
        for (place, topic) in Topic::ALL.iter().enumerate() {
            assert_eq!(topic.index(), place, "{}", topic.name());
        }
    }
}
