//! MCAP log of a closed-loop run, for Foxglove: the channels of [`crate::foxglove`] (`/tf` and
//! `/scene` as the Foxglove SDK's protobuf messages, our own channels as JSON with a JSON
//! Schema; see there for the table and the choice of encodings). Once
//! [`McapLogger::set_scene`] is called: the URDF as an attachment (named after the file, media
//! type `application/xml`), the robot's bodies (meshes included, decimated) as one `/robot`
//! message at the first sample's time, and a metadata record `scene` counting the visuals
//! drawn and naming each mesh not drawn (`mesh_warnings`, `warning_<k>`). How the run ended
//! ([`McapLogger::end`]) is the metadata record `run` (`status`, `reason`, `reason_kind`,
//! `end_s`; for a fall `fell_at_s`, `fall_foot`, `fall_constraint`, `fall_value`,
//! `fall_bound`), and a fall is also a `foxglove.Log` message (level WARNING) on `/events` at
//! its time, so Foxglove's Log panel and timeline show it. Each impact (a touchdown, a joint
//! reaching its stop; [`sea_loop::impacts`]) is a `foxglove.Log` message (level INFO) on
//! `/events` at its time, written when its window after closes (so up to 50 ms of samples
//! later in the file; readers that index by log time, as Foxglove, place it at its time).
//! Under `[walking]` ([`McapLogger::set_walking`]) `/scene` draws the walk and `/events` has
//! its planned lift-offs and touchdowns and the measured lift-offs.
//! Under unilateral contacts ([`McapLogger::set_contact_points`]) the contact points are on
//! `/contact_points` and in `/scene`; the contact check of the delivered wrenches, a
//! diagnostic there, is on `/contact_check` at every recorded sample, and each change of a
//! foot's verdict is a `foxglove.Log` on `/events` (WARNING when it starts violating a
//! constraint, INFO when it satisfies them again; [`McapLogger::contact_check`]). `/events`,
//! `/contact_points` and `/contact_check` are registered only when first needed, so a
//! bilateral run without a fall has none of them (under bilateral contacts the first
//! violation ends the run: it is the fall on `/events`).
//!
//! Chunks are LZ4-compressed. The file is finished (summary and index written) by
//! [`McapLogger::finish`] or, silently, when the logger is dropped, so an interrupted or
//! diverged run still leaves a readable file. [`McapLogger::flush`] closes the current chunk
//! and flushes it to disk, so even a killed process leaves data that MCAP recovery tools read;
//! [`ThreadedMcapLogger`] does so every second of wall time. [`McapSink`] is the log as a
//! [`RecordSink`] of the closed loop.

use crate::error::Error;
use crate::foxglove::{
    nanoseconds, FootRectangle, SampleEncoder, SceneSource, StaticScene, Topic, ROBOT_TOPIC,
};
use crate::meshes::visuals::MeshWarning;
use crate::Result;
use ::foxglove::messages::{log::Level, Log, Timestamp};
use ::foxglove::Encode;
use mcap::records::MessageHeader;
use mcap::records::Metadata;
use mcap::{Attachment, Compression, WriteOptions, Writer};
use sea_dyn::Model;
use sea_loop::{
    ContactCheckEvent, Impact, ImpactKind, RecordSink, RunEnd, RunInfo, Sample, VerdictChange,
};
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
mod threaded;
pub use threaded::ThreadedMcapLogger;

/// Incremental MCAP writer of [`Sample`]s; see the module documentation for the channels.
pub struct McapLogger {
    out: Output,
    encoder: SampleEncoder,
    /// MCAP channel id of each [`Topic`] (index [`Topic::index`]).
    channels: [u16; Topic::ALL.len()],
    /// The `/robot` channel and its message, until written (with the first sample).
    robot: Option<(u16, Vec<u8>)>,
    /// The `/contact_points` channel, once set ([`McapLogger::set_contact_points`]).
    contact_points: Option<u16>,
    /// The `/contact_check` channel, once a sample has the contact check.
    contact_check: Option<u16>,
    /// The `/events` channel, once an event is written.
    events: Option<u16>,
}

/// The MCAP writer with its sequence counter and serialisation buffer.
struct Output {
    /// `None` once finished.
    writer: Option<Writer<BufWriter<File>>>,
    /// The file, named in every error.
    path: PathBuf,
    /// Sequence number of the next message (monotonic over all channels).
    sequence: u32,
}

/// An MCAP error as a crate error naming `path`; I/O failures keep their OS cause (the `mcap`
/// crate's own message for them omits it).
fn mcap_error(path: &Path) -> impl Fn(mcap::McapError) -> Error + '_ {
    move |e| match e {
        mcap::McapError::Io(source) => Error::Io {
            path: path.display().to_string(),
            source,
        },
        other => Error::Log(format!("{}: {other}", path.display())),
    }
}

impl Output {
    /// The open writer and the file's path, or [`Error::Log`] once finished.
    fn open(&mut self) -> Result<(&mut Writer<BufWriter<File>>, &Path)> {
        match self.writer.as_mut() {
            Some(writer) => Ok((writer, &self.path)),
            None => Err(Error::Log("the log is already finished".into())),
        }
    }

    /// Registers the schema `(name, encoding, data)` and a channel on `topic` with
    /// `message_encoding`; returns the channel id.
    fn add_channel(
        &mut self,
        (name, encoding, data): (&str, &str, &[u8]),
        topic: &str,
        message_encoding: &str,
    ) -> Result<u16> {
        let (writer, path) = self.open()?;
        let schema_id = writer
            .add_schema(name, encoding, data)
            .map_err(mcap_error(path))?;
        writer
            .add_channel(schema_id, topic, message_encoding, &BTreeMap::new())
            .map_err(mcap_error(path))
    }

    /// Writes the encoded `message` on `channel` at `time` (ns).
    fn write(&mut self, channel: u16, time: u64, message: &[u8]) -> Result<()> {
        let sequence = self.sequence;
        let (writer, path) = self.open()?;
        let header = MessageHeader {
            channel_id: channel,
            sequence,
            log_time: time,
            publish_time: time,
        };
        let written = writer
            .write_to_known_channel(&header, message)
            .map_err(mcap_error(path));
        self.sequence = sequence.wrapping_add(1);
        written
    }

    /// Writes the summary and index, flushes and syncs the file; a no-op once finished.
    fn finish(&mut self) -> Result<()> {
        let Some(mut writer) = self.writer.take() else {
            return Ok(());
        };
        writer.finish().map_err(mcap_error(&self.path))?;
        let file = writer.into_inner().into_inner().map_err(|e| Error::Io {
            path: self.path.display().to_string(),
            source: e.into_error(),
        })?;
        file.sync_all().map_err(|source| Error::Io {
            path: self.path.display().to_string(),
            source,
        })
    }
}

impl Output {
    /// Registers `topic`'s schema and channel; returns the channel id.
    fn add_topic_channel(&mut self, topic: Topic) -> Result<u16> {
        let schema = topic.schema();
        let schema = (
            schema.name.as_str(),
            schema.encoding.as_str(),
            &schema.data[..],
        );
        self.add_channel(schema, topic.name(), &topic.message_encoding())
    }
}

/// Why an MCAP log must be a regular file, said in the errors that refuse another target.
pub const LOG_NEEDS_A_FILE: &str = "an MCAP log's writer seeks back over each chunk";

/// Refuses a log target that is not a regular file, before anything is written: the MCAP
/// writer seeks back over each chunk it finishes, which a device or a pipe cannot do (the run
/// would fail at its first chunk, a second of simulation in).
fn check_regular_file(file: &File, path: &Path) -> Result<()> {
    let metadata = file.metadata().map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    if metadata.is_file() {
        return Ok(());
    }
    Err(crate::output::not_a_regular_file(path, LOG_NEEDS_A_FILE))
}

/// Adds the schema and channel of every topic; returns the channel ids in [`Topic::ALL`] order.
fn add_channels(out: &mut Output) -> Result<[u16; Topic::ALL.len()]> {
    let mut channels = [0; Topic::ALL.len()];
    for (id, topic) in channels.iter_mut().zip(Topic::ALL) {
        *id = out.add_topic_channel(topic)?;
    }
    Ok(channels)
}

impl McapLogger {
    /// Creates (or truncates) the file at `path` and writes schemas/channels; see
    /// [`Self::from_file`].
    ///
    /// Errors: [`Error::Io`] when the file cannot be created or written, [`Error::Log`] when
    /// MCAP writing fails otherwise.
    pub fn create(
        path: &Path,
        model: &Model,
        elastic_joint_names: &[String],
        contact_names: &[String],
    ) -> Result<Self> {
        let file = File::create(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_file(file, path, model, elastic_joint_names, contact_names)
    }

    /// Writes the log into an open, empty `file` (e.g. a locked partial file of
    /// [`crate::output::OutputFile`]); `path` names it in errors. `elastic_joint_names` labels
    /// theta entries, `contact_names` the wrenches (contacts beyond the names are called
    /// `contact_<k>`).
    ///
    /// Errors: [`Error::Io`] when `file` is not a regular file (a device such as `/dev/null`,
    /// a pipe: the writer seeks back to finish each chunk) or when writing fails,
    /// [`Error::Log`] when MCAP writing fails otherwise.
    pub fn from_file(
        file: File,
        path: &Path,
        model: &Model,
        elastic_joint_names: &[String],
        contact_names: &[String],
    ) -> Result<Self> {
        check_regular_file(&file, path)?;
        let options = WriteOptions::new()
            .compression(Some(Compression::Lz4))
            .profile("")
            .library(concat!("sea_sim ", env!("CARGO_PKG_VERSION")));
        let writer = options
            .create(BufWriter::new(file))
            .map_err(mcap_error(path))?;
        let mut out = Output {
            writer: Some(writer),
            path: path.to_path_buf(),
            sequence: 0,
        };
        let channels = add_channels(&mut out)?;
        Ok(Self {
            out,
            encoder: SampleEncoder::new(model, elastic_joint_names, contact_names),
            channels,
            robot: None,
            contact_points: None,
            contact_check: None,
            events: None,
        })
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.out.path
    }

    /// Draws the robot of `source`: its bodies on `/robot` (written with the next sample), the
    /// support polygon on `/scene` from the next sample on; attaches the URDF to the log (named
    /// after the file, media type `application/xml`) and records the mesh warnings in the
    /// metadata record `scene`. Returns the mesh visuals not drawn.
    ///
    /// Errors: [`Error::Io`] when the URDF cannot be read or the attachment written,
    /// [`Error::Log`] when the URDF does not parse, the log is finished, or (strict source) a
    /// mesh cannot be drawn.
    pub fn set_scene(&mut self, source: &SceneSource) -> Result<Vec<MeshWarning>> {
        let frames = self.encoder.link_frames();
        let scene = StaticScene::build(source, &frames, self.encoder.contact_names())?;
        self.attach_scene(scene)
    }

    /// [`McapLogger::set_scene`] given up when `cancel` is raised while the meshes are read:
    /// the log then has no robot drawn (and no URDF attached); `Ok(None)`.
    pub fn set_scene_unless_cancelled(
        &mut self,
        source: &SceneSource,
        cancel: &AtomicBool,
    ) -> Result<Option<Vec<MeshWarning>>> {
        let frames = self.encoder.link_frames();
        let contacts = self.encoder.contact_names();
        match StaticScene::build_unless_cancelled(source, &frames, contacts, cancel)? {
            Some(scene) => self.attach_scene(scene).map(Some),
            None => Ok(None),
        }
    }

    /// Attaches the URDF of `scene`, its mesh warnings as metadata, and keeps its robot and
    /// support polygon for the next sample. Returns the mesh visuals not drawn.
    fn attach_scene(&mut self, mut scene: StaticScene) -> Result<Vec<MeshWarning>> {
        let (writer, path) = self.out.open()?;
        writer
            .attach(&Attachment {
                log_time: 0,
                create_time: 0,
                name: scene.file_name.clone(),
                media_type: URDF_MEDIA_TYPE.to_string(),
                data: Cow::Borrowed(&scene.urdf_text),
            })
            .map_err(mcap_error(path))?;
        writer
            .write_metadata(&scene_metadata(&scene))
            .map_err(mcap_error(path))?;
        let schema = Topic::Scene.schema();
        let channel = self.out.add_channel(
            (&schema.name, &schema.encoding, &schema.data),
            ROBOT_TOPIC,
            &Topic::Scene.message_encoding(),
        )?;
        self.robot = Some((channel, std::mem::take(&mut scene.robot)));
        let warnings = std::mem::take(&mut scene.warnings);
        self.encoder.set_scene(scene);
        Ok(warnings)
    }

    /// Writes one sample on every channel (log_time = publish_time = time_s in ns).
    ///
    /// Errors: [`Error::Log`] when the state does not have its layout's size, when `q` or `nu`
    /// do not have the model's sizes, when `contact_wrenches` or `planned_wrenches` is not a
    /// multiple of 6 long, when the logger is finished or when MCAP writing fails;
    /// [`Error::Io`] naming the file when the OS refuses a write.
    pub fn log(&mut self, sample: &Sample<'_>) -> Result<()> {
        if self.out.writer.is_none() {
            return Err(Error::Log("the log is already finished".into()));
        }
        if let Some((channel, robot)) = self.robot.take() {
            self.out
                .write(channel, crate::foxglove::nanoseconds(sample.time_s), &robot)?;
        }
        if !sample.contact_checks.is_empty() && self.contact_check.is_none() {
            self.contact_check = Some(self.out.add_topic_channel(Topic::ContactCheck)?);
        }
        let (out, channels) = (&mut self.out, &self.channels);
        let (points, check) = (self.contact_points, self.contact_check);
        let encoded = self.encoder.encode(sample, |topic, time, message| {
            let channel = match topic {
                Topic::ContactPoints => points,
                Topic::ContactCheck => check,
                _ => Some(channels[topic.index()]),
            };
            match channel {
                Some(channel) => out.write(channel, time, message),
                None => Ok(()),
            }
        });
        encoded?;
        for (time, message) in self.encoder.walking_events(sample)? {
            self.write_event(time, &message)?;
        }
        Ok(())
    }

    /// `[walking]`: draws the walk `gait` in `/scene` from the next sample on (the
    /// footsteps as the soles `foot`, none when `None`) and writes its lift-offs and
    /// touchdowns on `/events` ([`SampleEncoder::set_walking`]). Call it after
    /// [`Self::set_contact_points`].
    pub fn set_walking(&mut self, gait: &sea_ctrl::walking::Gait, foot: Option<FootRectangle>) {
        self.encoder.set_walking(gait, foot);
    }

    /// `[walking]`: draws `gait`, the walk as the controller changed it, from the next sample
    /// on ([`SampleEncoder::set_gait`]; its planned events after the last sample's time).
    pub fn set_gait(&mut self, gait: sea_ctrl::walking::Gait) {
        self.encoder.set_gait(gait);
    }

    /// Unilateral contacts: `counts[c]` points on contact `c` (the samples' contact points):
    /// registers `/contact_points` and draws the points in `/scene` from the next sample on.
    /// Empty counts (bilateral contacts) change nothing.
    ///
    /// Errors: [`Error::Log`] when the log is finished or MCAP writing fails.
    pub fn set_contact_points(&mut self, counts: &[usize]) -> Result<()> {
        if counts.iter().sum::<usize>() == 0 {
            return Ok(());
        }
        if self.contact_points.is_none() {
            self.contact_points = Some(self.out.add_topic_channel(Topic::ContactPoints)?);
        }
        self.encoder.set_contact_points(counts);
        Ok(())
    }

    /// Writes `message` (an encoded `foxglove.Log`) on `/events` at `time` (ns), registering
    /// the channel first when needed.
    fn write_event(&mut self, time: u64, message: &[u8]) -> Result<()> {
        let channel = match self.events {
            Some(channel) => channel,
            None => {
                let schema = Log::get_schema().expect("the SDK gives its schemas");
                let channel = self.out.add_channel(
                    (&schema.name, &schema.encoding, &schema.data),
                    EVENTS_TOPIC,
                    &Log::get_message_encoding(),
                )?;
                *self.events.insert(channel)
            }
        };
        self.out.write(channel, time, message)
    }

    /// Records `impact` on `/events`: a `foxglove.Log` (level INFO, name `sea_sim.touchdown`
    /// or `sea_sim.joint_stop`) at its time, its figures in the text (`impact_event`).
    ///
    /// Errors: [`Error::Log`] when the logger is finished or MCAP writing fails,
    /// [`Error::Io`] naming the file when the OS refuses a write.
    pub fn impact(&mut self, impact: &Impact) -> Result<()> {
        let (time, buffer) = impact_event(impact)?;
        self.write_event(time, &buffer)
    }

    /// Records a change of a foot's contact check (unilateral contacts) on `/events`: a
    /// `foxglove.Log` named `sea_sim.contact_check` at its time, level WARNING when the foot
    /// starts violating a constraint, INFO when it satisfies them again
    /// (`contact_check_event`).
    ///
    /// Errors: [`Error::Log`] when the logger is finished or MCAP writing fails,
    /// [`Error::Io`] naming the file when the OS refuses a write.
    pub fn contact_check(&mut self, event: &ContactCheckEvent) -> Result<()> {
        let (time, buffer) = contact_check_event(event)?;
        self.write_event(time, &buffer)
    }

    /// Names the disturbances of `/disturbances` by their links (`[[disturbances]]` order).
    pub fn set_disturbance_links(&mut self, links: &[String]) {
        self.encoder.set_disturbance_links(links);
    }

    /// Records how the run ended, `end` at `end_s` (the last sample's time): the metadata
    /// record `run` and, for a fall, a `foxglove.Log` warning on `/events` at the fall's time
    /// naming the foot, the constraint, its value and bound.
    ///
    /// Errors: [`Error::Log`] when the logger is finished or MCAP writing fails,
    /// [`Error::Io`] naming the file when the OS refuses a write.
    pub fn end(&mut self, end: &RunEnd, end_s: f64) -> Result<()> {
        let (writer, path) = self.out.open()?;
        writer
            .write_metadata(&run_metadata(end, end_s))
            .map_err(mcap_error(path))?;
        let Some((time, buffer)) = fall_event(end)? else {
            return Ok(());
        };
        self.write_event(time, &buffer)
    }

    /// Closes the current chunk and flushes everything written so far to the file (the file
    /// still lacks its summary until [`McapLogger::finish`]). Call it now and then in long runs
    /// so that a killed process loses little.
    ///
    /// Errors: [`Error::Io`] naming the file when the OS refuses the write.
    pub fn flush(&mut self) -> Result<()> {
        match self.out.writer.as_mut() {
            Some(writer) => writer.flush().map_err(mcap_error(&self.out.path)),
            None => Ok(()),
        }
    }

    /// Writes the summary/index and closes the file. Also done, ignoring errors, when the
    /// logger is dropped unfinished (so an interrupted or diverged run still leaves a readable
    /// file).
    ///
    /// Errors: [`Error::Io`] naming the file when the OS refuses a write (e.g. a full disk).
    pub fn finish(mut self) -> Result<()> {
        self.out.finish()
    }
}

impl Drop for McapLogger {
    fn drop(&mut self) {
        let _ = self.out.finish();
    }
}

/// The metadata record `scene`: visuals drawn, and each mesh not drawn.
fn scene_metadata(scene: &StaticScene) -> Metadata {
    let mut metadata = BTreeMap::from([
        ("visuals_drawn".to_string(), scene.visuals_drawn.to_string()),
        (
            "mesh_warnings".to_string(),
            scene.warnings.len().to_string(),
        ),
    ]);
    for (k, warning) in scene.warnings.iter().enumerate() {
        metadata.insert(format!("warning_{k}"), warning.to_string());
    }
    Metadata {
        name: "scene".to_string(),
        metadata,
    }
}

/// The metadata record `run`: how the run ended (see the module documentation).
fn run_metadata(end: &RunEnd, end_s: f64) -> Metadata {
    let mut metadata = BTreeMap::from([
        ("status".to_string(), end.status().to_string()),
        ("reason".to_string(), end.to_string()),
        (
            "reason_kind".to_string(),
            end.reason_kind().unwrap_or("").to_string(),
        ),
        ("end_s".to_string(), end_s.to_string()),
    ]);
    if let RunEnd::Fell { at_s, fall } = end {
        metadata.extend([
            ("fell_at_s".to_string(), at_s.to_string()),
            ("fall_foot".to_string(), fall.foot().to_string()),
            ("fall_link".to_string(), fall.link().to_string()),
            ("fall_constraint".to_string(), fall.kind().to_string()),
            ("fall_value".to_string(), fall.value().to_string()),
            ("fall_bound".to_string(), fall.bound().to_string()),
        ]);
    }
    Metadata {
        name: "run".to_string(),
        metadata,
    }
}

/// The topic of the run's events (a fall), `foxglove.Log`.
pub const EVENTS_TOPIC: &str = "/events";

/// A fall's `/events` message: its time [ns] and the encoded `foxglove.Log` (level WARNING,
/// name `sea_sim.fall`, the foot, constraint, value and bound in the text); `None` for a run
/// that did not fall. Shared by the MCAP log and the live view.
///
/// Errors: [`Error::Log`] when the message does not encode.
pub(crate) fn fall_event(end: &RunEnd) -> Result<Option<(u64, Vec<u8>)>> {
    let RunEnd::Fell { at_s, fall } = end else {
        return Ok(None);
    };
    let (constraint, value, bound) = (fall.kind(), fall.value(), fall.bound());
    let text = format!(
        "fell at t = {at_s} s: {fall} (constraint {constraint}, value {value}, bound {bound})"
    );
    log_event(*at_s, Level::Warning, text, "sea_sim.fall").map(Some)
}

/// An impact's `/events` message: its time [ns] and the encoded `foxglove.Log` (level INFO,
/// name `sea_sim.touchdown` or `sea_sim.joint_stop`, the text of [`Impact`]'s `Display`: the
/// foot or joint, the speeds before and after and their jump, the peaks after and before).
/// Shared by the MCAP log and the live view.
///
/// Errors: [`Error::Log`] when the message does not encode.
pub(crate) fn impact_event(impact: &Impact) -> Result<(u64, Vec<u8>)> {
    let name = match impact.kind {
        ImpactKind::Touchdown => "sea_sim.touchdown",
        ImpactKind::JointStop => "sea_sim.joint_stop",
    };
    log_event(impact.time_s, Level::Info, impact.to_string(), name)
}

/// A contact check's verdict change as an `/events` message: its time [ns] and the encoded
/// `foxglove.Log` (name `sea_sim.contact_check`; level WARNING when the foot starts violating
/// a constraint, the constraint, its value and bound in the text; INFO when it satisfies them
/// again, with the number of violating samples). Shared by the MCAP log and the live view.
///
/// Errors: [`Error::Log`] when the message does not encode.
pub(crate) fn contact_check_event(event: &ContactCheckEvent) -> Result<(u64, Vec<u8>)> {
    let (level, text) = match &event.change {
        VerdictChange::Violated(constraint) => (
            Level::Warning,
            format!(
                "{event} (constraint {}, value {}, bound {})",
                constraint.kind(),
                constraint.value(),
                constraint.bound()
            ),
        ),
        VerdictChange::Satisfied { .. } => (Level::Info, event.to_string()),
    };
    log_event(event.time_s, level, text, "sea_sim.contact_check")
}

/// A `foxglove.Log` at `time_s` with `level`, `text` and `name`, encoded, with its time [ns].
pub(crate) fn log_event(
    time_s: f64,
    level: Level,
    text: String,
    name: &str,
) -> Result<(u64, Vec<u8>)> {
    let time = nanoseconds(time_s);
    let message = Log {
        timestamp: Some(Timestamp::new(
            u32::try_from(time / 1_000_000_000).unwrap_or(u32::MAX),
            (time % 1_000_000_000) as u32,
        )),
        level: level as i32,
        message: text,
        name: name.to_string(),
        ..Default::default()
    };
    let mut buffer = Vec::new();
    message
        .encode(&mut buffer)
        .map_err(|e| Error::Log(format!("{EVENTS_TOPIC}: {e}")))?;
    Ok((time, buffer))
}

/// Media type of the URDF attachment.
const URDF_MEDIA_TYPE: &str = "application/xml";

impl std::fmt::Debug for McapLogger {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McapLogger")
            .field("path", &self.out.path)
            .field("finished", &self.out.writer.is_none())
            .field("messages", &self.out.sequence)
            .finish()
    }
}

/// The MCAP log as a sink of the closed loop: the file is created by `begin` and finished
/// (summary and index written) by `finish`, or when the sink is dropped, so a diverged or
/// interrupted run leaves a readable log. Memory stays bounded: samples wait in the writer
/// thread's bounded queue.
pub struct McapSink {
    path: PathBuf,
    /// Searched first for the URDF's `package://` meshes.
    package_dirs: Vec<PathBuf>,
    logger: Option<ThreadedMcapLogger>,
    /// The meshes that could not be drawn (kept in the log's metadata too).
    warnings: Vec<MeshWarning>,
}

impl McapSink {
    /// A sink that will write `path`.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            package_dirs: Vec::new(),
            warnings: Vec::new(),
            logger: None,
        }
    }

    /// The meshes of the robot's scene that could not be drawn (a missing file, an unresolved
    /// `package://` URI, a mesh over its budget), known once the run has begun; the caller
    /// reports them (the library prints nothing). Each is also in the log's metadata.
    pub fn warnings(&self) -> &[MeshWarning] {
        &self.warnings
    }

    /// The same sink looking for `package://` meshes in `dirs` first (then the environment's
    /// package directories, then above the URDF).
    pub fn with_package_dirs(mut self, dirs: &[PathBuf]) -> Self {
        self.package_dirs = dirs.to_vec();
        self
    }
}

impl RecordSink for McapSink {
    fn begin(&mut self, run: &RunInfo<'_>) -> Result<()> {
        let mut logger =
            McapLogger::create(&self.path, run.model, run.elastic_joints, run.contacts)?;
        logger.set_disturbance_links(run.disturbance_links);
        logger.set_contact_points(run.contact_points)?;
        let source = SceneSource::of_run(run.scene).with_package_dirs(&self.package_dirs);
        if let Some(gait) = run.walking {
            logger.set_walking(gait, source.foot);
        }
        let warnings = logger.set_scene_unless_cancelled(&source, run.cancel)?;
        self.warnings = warnings.unwrap_or_default();
        self.logger = Some(ThreadedMcapLogger::spawn(logger));
        Ok(())
    }

    fn record(&mut self, sample: &Sample<'_>) -> Result<()> {
        match self.logger.as_mut() {
            Some(logger) => logger.log(sample),
            None => Ok(()),
        }
    }

    fn walking(&mut self, gait: &sea_ctrl::walking::Gait) -> Result<()> {
        match self.logger.as_mut() {
            Some(logger) => logger.set_gait(gait),
            None => Ok(()),
        }
    }

    fn impact(&mut self, impact: &Impact) -> Result<()> {
        match self.logger.as_mut() {
            Some(logger) => logger.impact(impact),
            None => Ok(()),
        }
    }

    fn contact_check(&mut self, event: &ContactCheckEvent) -> Result<()> {
        match self.logger.as_mut() {
            Some(logger) => logger.contact_check(event),
            None => Ok(()),
        }
    }

    fn end(&mut self, end: &RunEnd) -> Result<()> {
        match self.logger.as_mut() {
            Some(logger) => logger.end(end),
            None => Ok(()),
        }
    }

    fn finish(&mut self) -> Result<()> {
        match self.logger.take() {
            Some(logger) => logger.finish(),
            None => Ok(()),
        }
    }
}
