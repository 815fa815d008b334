//! `sea-sim run --live`: a WebSocket client offering the Foxglove subprotocols connects to the
//! address the binary prints (the SDK 0.30 server negotiates `foxglove.sdk.v1`, the renamed
//! `foxglove.websocket.v1` whose messages are the same), receives the advertised channels and, once subscribed, messages;
//! the run is paced to the wall clock. Bounded in time: every read has a deadline.

use std::collections::{BTreeMap, BTreeSet};
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::client::IntoClientRequest;
use tungstenite::Message;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/paper/tracking.toml"
);

/// Longest wait for any step of the test.
const DEADLINE: Duration = Duration::from_secs(60);

/// The child process, killed when the test ends however it ends.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts `sea-sim run --live --port 0` for `duration_s` simulated seconds; returns the
/// process and the port it printed.
fn start(duration_s: f64) -> (Running, u16) {
    start_scenario(SCENARIO, duration_s, &[])
}

/// [`start`] for `scenario` with the `--set` overrides `overrides`.
fn start_scenario(scenario: &str, duration_s: f64, overrides: &[&str]) -> (Running, u16) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sea-sim"));
    command.args(["run", scenario, "--live", "--port", "0", "--quiet"]);
    for value in overrides {
        command.args(["--set", value]);
    }
    let child = command
        .arg("--set")
        .arg(format!("simulation.duration_s={duration_s}"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sea-sim starts");
    let mut running = Running(child);
    let stderr = running.0.stderr.take().unwrap();
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = sender.send(line);
        }
    });
    loop {
        let line = receiver
            .recv_timeout(DEADLINE)
            .expect("sea-sim prints the live address");
        if let Some(address) = line.split("ws://127.0.0.1:").nth(1) {
            let port: String = address.chars().take_while(char::is_ascii_digit).collect();
            return (running, port.parse().expect("a port"));
        }
    }
}

#[test]
fn a_websocket_client_receives_the_advertised_channels_and_messages() {
    let duration_s = 4.0;
    let started = Instant::now();
    let (_running, port) = start(duration_s);

    let (mut socket, response) = connect(port);
    assert_eq!(
        response.headers()["Sec-WebSocket-Protocol"],
        "foxglove.sdk.v1"
    );

    // Every channel is advertised with its encoding and schema name (and `/robot`).
    let expected: BTreeSet<&str> = sea_sim::foxglove::Topic::ALL
        .iter()
        .map(|t| t.name())
        .chain([
            sea_sim::foxglove::ROBOT_TOPIC,
            sea_sim::mcap_log::EVENTS_TOPIC,
        ])
        .collect();
    let mut advertised: BTreeMap<String, serde_json::Value> = BTreeMap::new();
    while advertised.len() < expected.len() {
        let json = next_json(&mut socket, started, "advertise");
        if json["op"] == "advertise" {
            for channel in json["channels"].as_array().unwrap() {
                advertised.insert(channel["topic"].as_str().unwrap().into(), channel.clone());
            }
        }
    }
    let topics: BTreeSet<&str> = advertised.keys().map(String::as_str).collect();
    assert_eq!(topics, expected);
    assert_eq!(advertised["/tf"]["encoding"], "protobuf");
    assert_eq!(advertised["/scene"]["schemaName"], "foxglove.SceneUpdate");
    assert_eq!(advertised["/robot"]["schemaName"], "foxglove.SceneUpdate");
    assert_eq!(advertised["/com"]["encoding"], "json");

    // Subscribed to /com, the client receives message data (opcode 0x01) with JSON in it.
    subscribe(&mut socket, 7, &advertised["/com"]["id"]);
    let mut times_ns = Vec::new();
    let mut first_at = None;
    // Until the messages span SPAN_S of simulated time.
    const SPAN_S: f64 = 0.5;
    while times_ns.len() < 2 || (times_ns[times_ns.len() - 1] - times_ns[0]) as f64 * 1e-9 < SPAN_S
    {
        let data = next_binary(&mut socket, started, "messages");
        assert_eq!(data[0], 0x01, "message data");
        assert_eq!(u32::from_le_bytes(data[1..5].try_into().unwrap()), 7);
        times_ns.push(u64::from_le_bytes(data[5..13].try_into().unwrap()));
        let com: serde_json::Value = serde_json::from_slice(&data[13..]).expect("JSON /com");
        assert_eq!(com["com"].as_array().unwrap().len(), 3);
        first_at.get_or_insert_with(Instant::now);
    }
    // Real-time pace: the messages took their simulated span in wall time (within slack).
    let simulated = (times_ns[times_ns.len() - 1] - times_ns[0]) as f64 * 1e-9;
    let wall = first_at.unwrap().elapsed().as_secs_f64();
    assert!(simulated > 0.0);
    assert!(
        wall > 0.8 * simulated,
        "wall {wall:.3} s for {simulated:.3} s simulated: not paced"
    );
    let _ = socket.close(None);
}

/// The client's end of the live view.
type Socket = tungstenite::WebSocket<TcpStream>;

/// The next text message of the server, as JSON, within the deadline counted from `started`
/// (`what` names the wait in the failure).
fn next_json(socket: &mut Socket, started: Instant, what: &str) -> serde_json::Value {
    loop {
        assert!(started.elapsed() < DEADLINE, "{what} within the deadline");
        if let Message::Text(text) = socket.read().expect("a message") {
            return serde_json::from_str(&text).unwrap();
        }
    }
}

/// The next binary message (message data) of the server, within the deadline counted from
/// `started`.
fn next_binary(socket: &mut Socket, started: Instant, what: &str) -> Vec<u8> {
    loop {
        assert!(started.elapsed() < DEADLINE, "{what} within the deadline");
        if let Message::Binary(data) = socket.read().expect("a message") {
            return data.to_vec();
        }
    }
}

/// Subscribes the client's subscription `id` to the channel `channel_id`.
fn subscribe(socket: &mut Socket, id: u32, channel_id: &serde_json::Value) {
    let request = serde_json::json!({
        "op": "subscribe",
        "subscriptions": [{"id": id, "channelId": channel_id}],
    });
    socket
        .send(Message::text(request.to_string()))
        .expect("subscribe");
}

/// The handshake of a client offering the Foxglove subprotocols, on `port`: the socket and
/// the server's response.
fn connect(port: u16) -> (Socket, tungstenite::handshake::client::Response) {
    let stream = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    stream.set_read_timeout(Some(DEADLINE)).unwrap();
    let mut request = format!("ws://127.0.0.1:{port}")
        .into_client_request()
        .unwrap();
    request.headers_mut().insert(
        "Sec-WebSocket-Protocol",
        "foxglove.sdk.v1, foxglove.websocket.v1".parse().unwrap(),
    );
    tungstenite::client(request, stream).expect("handshake")
}

/// A run that falls (a 20 N s push on the pelvis of the two-feet iCub, about 1.08 s into the
/// run): a client subscribed to `/events` receives the fall's `foxglove.Log` message.
#[test]
fn a_fall_reaches_the_live_view_on_events() {
    const PUSH: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/robot_rate/push_two_feet.toml"
    );
    let started = Instant::now();
    let push = "disturbances=[{link = \"root_link\", force = [200.0, 0.0, 0.0], start_s = 1.0, \
                duration_s = 0.1}]";
    // As measured, with the fixed estimates (the file's stiffness identification off).
    let fixed = "controller.stiffness_identification=false";
    // The feet welded, the fall the wrench check's (as tests/support's `WELDED_PUSH`).
    let welded = [
        "plant.contact_model=\"bilateral\"",
        "simulation.stop_at_joint_limits=true",
    ];
    let (_running, port) = start_scenario(PUSH, 3.0, &[welded[0], welded[1], fixed, push]);
    let (mut socket, _) = connect(port);
    let events = loop {
        let json = next_json(&mut socket, started, "advertise");
        let channels = json["channels"].as_array().cloned().unwrap_or_default();
        if let Some(channel) = channels.iter().find(|c| c["topic"] == "/events") {
            assert_eq!(channel["schemaName"], "foxglove.Log");
            break channel["id"].clone();
        }
    };
    subscribe(&mut socket, 3, &events);
    let data = next_binary(&mut socket, started, "the fall");
    assert_eq!(u32::from_le_bytes(data[1..5].try_into().unwrap()), 3);
    let text = String::from_utf8_lossy(&data[13..]);
    assert!(text.contains("fell at t = 1.0"), "{text}");
    assert!(text.contains("center_of_pressure"), "{text}");
    let _ = socket.close(None);
}

/// Feet on the ground (the push scenario as shipped: unilateral contacts): a client subscribed
/// to `/contact_points` receives each sole's points with their forces, which carry the robot's
/// weight, and on `/contact_check` both feet's verdicts, none violated while it stands.
#[test]
fn the_contact_points_and_their_check_reach_the_live_view() {
    const PUSH: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/robot_rate/push_two_feet.toml"
    );
    let started = Instant::now();
    let no_push = "disturbances=[]";
    let (_running, port) = start_scenario(PUSH, 2.0, &[no_push]);
    let (mut socket, _) = connect(port);
    let mut ids = BTreeMap::new();
    while ids.len() < 2 {
        let json = next_json(&mut socket, started, "advertise");
        for channel in json["channels"].as_array().cloned().unwrap_or_default() {
            let topic = channel["topic"].as_str().unwrap_or_default().to_string();
            if topic == "/contact_points" || topic == "/contact_check" {
                assert_eq!(channel["encoding"], "json", "{topic}");
                ids.insert(topic, channel["id"].clone());
            }
        }
    }
    subscribe(&mut socket, 5, &ids["/contact_points"]);
    let data = next_binary(&mut socket, started, "contact points");
    assert_eq!(u32::from_le_bytes(data[1..5].try_into().unwrap()), 5);
    let points: serde_json::Value = serde_json::from_slice(&data[13..]).expect("JSON points");
    let points = points["points"].as_array().expect("points").clone();
    assert_eq!(points.len(), 8, "four corners per sole");
    let normal: f64 = points.iter().map(|p| p["force"][2].as_f64().unwrap()).sum();
    let weight = 33.0 * 9.81;
    assert!(
        (normal - weight).abs() < 0.1 * weight,
        "normal forces {normal} N"
    );
    assert!(points.iter().all(|p| p["active"] == true), "{points:?}");
    subscribe(&mut socket, 6, &ids["/contact_check"]);
    let check = loop {
        let data = next_binary(&mut socket, started, "contact check");
        if u32::from_le_bytes(data[1..5].try_into().unwrap()) == 6 {
            break serde_json::from_slice::<serde_json::Value>(&data[13..]).expect("JSON check");
        }
    };
    let contacts = check["contacts"].as_array().expect("contacts");
    let frames: Vec<&str> = contacts
        .iter()
        .map(|c| c["contact"].as_str().unwrap())
        .collect();
    assert_eq!(frames, ["l_sole", "r_sole"]);
    assert!(contacts.iter().all(|c| c["violated"].is_null()), "{check}");
    let _ = socket.close(None);
}

#[test]
fn a_port_in_use_is_refused_naming_the_live_view_and_the_port() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
    let port = taken.local_addr().unwrap().port().to_string();
    let output = Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .args(["run", SCENARIO, "--live", "--port", &port, "--quiet"])
        .args(["--set", "simulation.duration_s=0.01"])
        .output()
        .expect("sea-sim runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{stderr}");
    assert!(
        stderr.contains("Foxglove live view") && stderr.contains(&port),
        "{stderr}"
    );
    assert!(!stderr.contains("MCAP"), "{stderr}");
}
