//! Live view: the channels of [`crate::foxglove`] served over the Foxglove WebSocket protocol
//! (`foxglove.websocket.v1`) by the Foxglove SDK's server, on 127.0.0.1 only, at real-time
//! pace: each sample is published when the wall clock since the first sample reaches its
//! simulated time, so the robot moves in the Foxglove app ("Open connection", Foxglove
//! WebSocket, `ws://127.0.0.1:PORT`) as fast as it would move in reality.
//!
//! A fall is published on `/events` (`foxglove.Log`, the MCAP log's message) when the run
//! ends, and each impact (touchdown, joint stop) when its window closes, so the app's Log
//! panel shows them live. Under unilateral contacts `/contact_points` and `/contact_check`
//! are advertised too, and each change of a foot's contact check is published on `/events`
//! after its sample.
//!
//! Pacing sleeps in [`RecordSink::record`], i.e. on the loop's thread: the loop is held back to
//! real time by design. Encoding runs there too, in the time the loop would otherwise sleep;
//! a run slower than real time is not slowed further by more than the encoding (about a fifth
//! of a tick).

use super::{SampleEncoder, SceneSource, StaticScene, Topic, ROBOT_TOPIC};
use crate::error::Error;
use crate::mcap_log::{contact_check_event, fall_event, impact_event, EVENTS_TOPIC};
use crate::Result;
use ::foxglove::messages::Log;
use ::foxglove::{ChannelBuilder, Context, Encode, PartialMetadata, RawChannel, WebSocketServer};
use sea_loop::{ContactCheckEvent, Impact, RecordSink, RunEnd, RunInfo, Sample};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The only address the live server listens on: the view is for this machine.
pub const LIVE_HOST: &str = "127.0.0.1";

/// Foxglove's default WebSocket port (the app's "Open connection" suggests it).
pub const DEFAULT_LIVE_PORT: u16 = 8765;

/// A running live server with one SDK channel per [`Topic`].
pub struct LiveServer {
    /// The SDK context the channels and the server share (kept for their lifetime).
    context: Arc<Context>,
    server: Option<::foxglove::WebSocketServerHandle>,
    channels: Vec<Arc<RawChannel>>,
    /// `/robot`, republished every [`ROBOT_REPUBLISH_INTERVAL`].
    robot: Arc<RawChannel>,
    /// `/events`: a fall, when the run ends, and the impacts.
    events: Arc<RawChannel>,
    /// `/contact_points` under unilateral contacts ([`LiveServer::add_contact_points`]).
    contact_points: Option<Arc<RawChannel>>,
    /// `/contact_check` under unilateral contacts ([`LiveServer::add_contact_points`]).
    contact_check: Option<Arc<RawChannel>>,
}

/// Wall time between two `/robot` messages of the live view: a client that connects late
/// sees the robot within this time.
const ROBOT_REPUBLISH_INTERVAL: Duration = Duration::from_secs(1);

/// Wall time the server stays up after the run ends, so that the last messages (and a fall on
/// `/events`) reach the clients before it closes their connections.
const LINGER: Duration = Duration::from_millis(500);

impl LiveServer {
    /// Starts the server on [`LIVE_HOST`]:`port` (0: any free port) and advertises every
    /// channel.
    ///
    /// Errors: [`Error::Output`] when the server cannot start (e.g. the port is taken).
    pub fn start(port: u16) -> Result<Self> {
        let context = Context::new();
        let channel = |name: &str, topic: Topic| topic_channel(&context, name, topic);
        let channels = Topic::ALL
            .iter()
            .map(|topic| channel(topic.name(), *topic))
            .collect::<Result<Vec<_>>>()?;
        let robot = channel(ROBOT_TOPIC, Topic::Scene)?;
        let events = ChannelBuilder::new(EVENTS_TOPIC)
            .context(&context)
            .message_encoding(Log::get_message_encoding())
            .schema(Log::get_schema())
            .build_raw()
            .map_err(|e| {
                Error::Output(format!("Foxglove live view, channel {EVENTS_TOPIC}: {e}"))
            })?;
        let server = WebSocketServer::new()
            .name("sea-sim")
            .context(&context)
            .bind(LIVE_HOST, port)
            .start_blocking()
            .map_err(|e| {
                Error::Output(format!(
                    "Foxglove live view, server on {LIVE_HOST}:{port}: {e}"
                ))
            })?;
        Ok(Self {
            context,
            server: Some(server),
            channels,
            robot,
            events,
            contact_points: None,
            contact_check: None,
        })
    }

    /// Advertises `/contact_points` and `/contact_check` (unilateral contacts), once.
    ///
    /// Errors: [`Error::Output`] when a channel cannot be built.
    fn add_contact_points(&mut self) -> Result<()> {
        let context = &self.context;
        for (slot, topic) in [
            (&mut self.contact_points, Topic::ContactPoints),
            (&mut self.contact_check, Topic::ContactCheck),
        ] {
            if slot.is_none() {
                *slot = Some(topic_channel(context, topic.name(), topic)?);
            }
        }
        Ok(())
    }

    /// The port the server listens on.
    pub fn port(&self) -> u16 {
        self.server.as_ref().map_or(0, |s| s.port())
    }

    /// Publishes `message` on `topic` at `time` (ns).
    fn publish(&self, topic: Topic, time: u64, message: &[u8]) {
        let channel = match topic {
            Topic::ContactPoints => self.contact_points.as_ref(),
            Topic::ContactCheck => self.contact_check.as_ref(),
            _ => Some(&self.channels[topic.index()]),
        };
        let Some(channel) = channel else {
            return;
        };
        channel.log_with_meta(message, PartialMetadata::with_log_time(time));
    }

    /// Closes the channels and stops the server.
    fn stop(&mut self) {
        let others = [&self.robot, &self.events].into_iter();
        for channel in self
            .channels
            .iter()
            .chain(others)
            .chain(&self.contact_points)
            .chain(&self.contact_check)
        {
            channel.close();
        }
        if let Some(server) = self.server.take() {
            drop(server.stop());
        }
    }
}

/// The SDK channel `name` of `topic` in `context`.
///
/// Errors: [`Error::Output`] when the channel cannot be built.
fn topic_channel(context: &Arc<Context>, name: &str, topic: Topic) -> Result<Arc<RawChannel>> {
    ChannelBuilder::new(name)
        .context(context)
        .message_encoding(topic.message_encoding())
        .schema(topic.schema())
        .build_raw()
        .map_err(|e| Error::Output(format!("Foxglove live view, channel {name}: {e}")))
}

impl Drop for LiveServer {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The live view as a [`RecordSink`]: the server starts at [`LiveSink::start`] (so its port is
/// known, and can be printed, before the run), the robot's scene is set by `begin`, samples
/// are published at real-time pace, and `finish` stops the server.
pub struct LiveSink {
    server: LiveServer,
    encoder: Option<SampleEncoder>,
    /// Wall time and simulated time of the first sample.
    origin: Option<(Instant, f64)>,
    /// The `/robot` message and when it was last published.
    robot: Option<(Vec<u8>, Option<Instant>)>,
    /// Searched first for the URDF's `package://` meshes.
    package_dirs: Vec<std::path::PathBuf>,
}

impl LiveSink {
    /// Starts the server on [`LIVE_HOST`]:`port` (0: any free port).
    ///
    /// Errors: [`Error::Output`] when the server cannot start.
    pub fn start(port: u16) -> Result<Self> {
        Ok(Self {
            server: LiveServer::start(port)?,
            encoder: None,
            origin: None,
            robot: None,
            package_dirs: Vec::new(),
        })
    }

    /// The same sink looking for `package://` meshes in `dirs` first (then the environment's
    /// package directories, then above the URDF).
    pub fn with_package_dirs(mut self, dirs: &[std::path::PathBuf]) -> Self {
        self.package_dirs = dirs.to_vec();
        self
    }

    /// The port the server listens on.
    pub fn port(&self) -> u16 {
        self.server.port()
    }

    /// Sleeps until the wall clock since the first sample reaches `time_s` minus its time.
    fn pace(&mut self, time_s: f64) {
        let (wall_start, sim_start) = *self.origin.get_or_insert((Instant::now(), time_s));
        let due = Duration::try_from_secs_f64(time_s - sim_start).unwrap_or(Duration::ZERO);
        if let Some(wait) = due.checked_sub(wall_start.elapsed()) {
            std::thread::sleep(wait);
        }
    }
}

impl RecordSink for LiveSink {
    fn begin(&mut self, run: &RunInfo<'_>) -> Result<()> {
        let mut encoder = SampleEncoder::new(run.model, run.elastic_joints, run.contacts);
        let source = SceneSource::of_run(run.scene).with_package_dirs(&self.package_dirs);
        let frames = encoder.link_frames();
        let built =
            StaticScene::build_unless_cancelled(&source, &frames, run.contacts, run.cancel)?;
        if let Some(mut scene) = built {
            self.robot = Some((std::mem::take(&mut scene.robot), None));
            encoder.set_scene(scene);
        }
        encoder.set_disturbance_links(run.disturbance_links);
        encoder.set_contact_points(run.contact_points);
        if let Some(gait) = run.walking {
            encoder.set_walking(gait, SceneSource::of_run(run.scene).foot);
        }
        if encoder.has_contact_points() {
            self.server.add_contact_points()?;
        }
        self.encoder = Some(encoder);
        Ok(())
    }

    fn impact(&mut self, impact: &Impact) -> Result<()> {
        let (time, message) = impact_event(impact)?;
        let meta = PartialMetadata::with_log_time(time);
        self.server.events.log_with_meta(&message, meta);
        Ok(())
    }

    fn walking(&mut self, gait: &sea_ctrl::walking::Gait) -> Result<()> {
        if let Some(encoder) = self.encoder.as_mut() {
            encoder.set_gait(gait.clone());
        }
        Ok(())
    }

    fn contact_check(&mut self, event: &ContactCheckEvent) -> Result<()> {
        let (time, message) = contact_check_event(event)?;
        let meta = PartialMetadata::with_log_time(time);
        self.server.events.log_with_meta(&message, meta);
        Ok(())
    }

    fn record(&mut self, sample: &Sample<'_>) -> Result<()> {
        self.pace(sample.time_s);
        let Some(encoder) = self.encoder.as_mut() else {
            return Ok(());
        };
        let server = &self.server;
        if let Some((robot, published)) = self.robot.as_mut() {
            if published.is_none_or(|at| at.elapsed() >= ROBOT_REPUBLISH_INTERVAL) {
                let time = super::nanoseconds(sample.time_s);
                server
                    .robot
                    .log_with_meta(robot, PartialMetadata::with_log_time(time));
                *published = Some(Instant::now());
            }
        }
        encoder.encode(sample, |topic, time, message| {
            server.publish(topic, time, message);
            Ok(())
        })?;
        for (time, message) in encoder.walking_events(sample)? {
            let meta = PartialMetadata::with_log_time(time);
            server.events.log_with_meta(&message, meta);
        }
        Ok(())
    }

    fn end(&mut self, end: &RunEnd) -> Result<()> {
        if let Some((time, message)) = fall_event(end)? {
            let meta = PartialMetadata::with_log_time(time);
            self.server.events.log_with_meta(&message, meta);
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<()> {
        std::thread::sleep(LINGER);
        self.server.stop();
        Ok(())
    }
}
