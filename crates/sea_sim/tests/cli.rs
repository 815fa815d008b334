//! The `sea-sim` command line, run as a real subprocess: help, argument errors, signals, safe
//! output files, full disks and closed pipes.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_sea-sim");
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// Longest any subprocess may take before the test fails (and the process is killed).
const TIMEOUT: Duration = Duration::from_secs(60);

/// A fresh folder in the temporary directory, removed on drop, holding a copy of the paper's
/// tracking scenario (URDF path made absolute), so no test can touch the repository's files.
pub(super) struct Workspace(PathBuf);

impl Workspace {
    pub(super) fn new(tag: &str) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos();
        let dir =
            std::env::temp_dir().join(format!("sea_sim_cli_{tag}_{}_{nanos}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = std::fs::read_to_string(format!("{REPO}/scenarios/paper/tracking.toml"))
            .expect("the tracking scenario");
        let urdf = Path::new(REPO)
            .join("urdf/icub25.urdf")
            .canonicalize()
            .unwrap();
        let text = text.replace("../../urdf/icub25.urdf", urdf.to_str().unwrap());
        assert!(text.contains(urdf.to_str().unwrap()), "URDF path rewritten");
        // The sampled-data setting these tests were written for (the paper's file is
        // continuous): 1 kHz zero-order hold, 1 ms plant step.
        let text = text
            .replace(
                "sampling = \"continuous\"",
                "sampling = \"zero_order_hold\"",
            )
            .replace("dt = 0.00025", "dt = 0.001");
        assert!(text.contains("zero_order_hold"), "sampling rewritten");
        std::fs::write(dir.join("scenario.toml"), text).unwrap();
        Self(dir)
    }

    pub(super) fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    fn scenario(&self) -> String {
        self.path("scenario.toml").display().to_string()
    }
}

impl Drop for Workspace {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `sea-sim ARGS` to completion (killed after [`TIMEOUT`]).
pub(crate) fn sea_sim(args: &[&str]) -> Output {
    let child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sea-sim starts");
    let (sender, receiver) = std::sync::mpsc::channel();
    let id = child.id();
    std::thread::spawn(move || {
        let _ = sender.send(child.wait_with_output());
    });
    match receiver.recv_timeout(TIMEOUT) {
        Ok(output) => output.expect("sea-sim output"),
        Err(_) => {
            signal(id, "KILL");
            panic!("sea-sim {args:?} did not finish within {TIMEOUT:?}");
        }
    }
}

pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Sends `kill -SIGNAL` to `pid`.
fn signal(pid: u32, name: &str) {
    let status = Command::new("kill")
        .arg(format!("-{name}"))
        .arg(pid.to_string())
        .status()
        .expect("kill runs");
    assert!(status.success(), "kill -{name} {pid}");
}

/// A run in the background whose stderr lines arrive on a channel.
pub(super) struct Running {
    child: Child,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Running {
    /// Starts `sea-sim run SCENARIO ARGS` (progress as plain lines: stderr is a pipe).
    fn start(scenario: &str, args: &[&str]) -> Self {
        Self::start_command(("run", scenario), args, Stdio::null())
    }

    /// Starts `sea-sim COMMAND SCENARIO ARGS` with its stdout to `stdout`.
    pub(super) fn start_command(
        (command, scenario): (&str, &str),
        args: &[&str],
        stdout: Stdio,
    ) -> Self {
        let mut child = Command::new(BIN)
            .arg(command)
            .arg(scenario)
            .args(args)
            .stdin(Stdio::null())
            .stdout(stdout)
            .stderr(Stdio::piped())
            .spawn()
            .expect("sea-sim starts");
        let stderr = child.stderr.take().unwrap();
        let (sender, lines) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if sender.send(line).is_err() {
                    break;
                }
            }
        });
        Self {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits for the first progress line (the closed loop is running).
    fn wait_for_progress(&mut self) {
        self.wait_for_line("t = ");
    }

    /// Waits for the first line of stderr that contains `text`; returns it.
    pub(super) fn wait_for_line(&mut self, text: &str) -> String {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    let found = line.contains(text);
                    self.seen.push(line.clone());
                    if found {
                        return line;
                    }
                }
                Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => {
                    let _ = self.child.kill();
                    panic!("no line with '{text}'; stderr: {:?}", self.seen);
                }
            }
        }
    }

    /// The process id.
    pub(super) fn id(&self) -> u32 {
        self.child.id()
    }

    pub(super) fn signal(&self, name: &str) {
        signal(self.child.id(), name);
    }

    /// Waits for the exit; returns the code (None when killed by a signal) and stderr.
    pub(super) fn wait(mut self) -> (Option<i32>, String) {
        let deadline = Instant::now() + TIMEOUT;
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            if Instant::now() > deadline {
                let _ = self.child.kill();
                panic!("sea-sim did not stop; stderr: {:?}", self.seen);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        self.seen.extend(self.lines.try_iter());
        (status.code(), self.seen.join("\n"))
    }
}

impl Drop for Running {
    /// A failed test does not leave a run going.
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The summary JSON at `path`.
fn summary(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).expect("summary JSON")
}

/// Reads a finished MCAP file: its summary section is present; returns the message count
/// (checked against the messages actually read).
fn finished_mcap_messages(path: &Path) -> u64 {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let summary = mcap::Summary::read(&bytes)
        .expect("summary readable")
        .expect("summary section present");
    let count = summary.stats.expect("statistics").message_count;
    let mut read = 0;
    for message in mcap::MessageStream::new(&bytes).expect("stream") {
        message.expect("message");
        read += 1;
    }
    assert_eq!(read, count, "statistics count the messages");
    count
}

/// Long enough that no run ends by itself before the test stops it (about 30 s of wall time).
const LONG_RUN: &str = "simulation.duration_s=300";
const SHORT_RUN: &str = "simulation.duration_s=0.3";

/// `out` is exit status 1 with an error naming `path` and saying `why`.
fn assert_refused(out: &Output, path: &str, why: &str) {
    let message = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{path}: {message}");
    assert!(
        message.contains(path) && message.contains(why),
        "{path}: {message}"
    );
}

/// `sea-sim run` of the workspace's scenario for [`SHORT_RUN`], quiet, with `options` after.
fn short_run(ws: &Workspace, options: &[&str]) -> Output {
    let scenario = ws.scenario();
    let mut args = vec!["run", scenario.as_str(), "--set", SHORT_RUN, "--quiet"];
    args.extend_from_slice(options);
    sea_sim(&args)
}

#[test]
fn help_lists_subcommands_and_each_subcommand_documents_its_options() {
    let top = sea_sim(&["--help"]);
    assert_eq!(top.status.code(), Some(0));
    let top = text(&top.stdout);
    for command in ["run", "bench", "sweep", "margin"] {
        assert!(top.contains(command), "--help lacks {command}: {top}");
    }

    let run = sea_sim(&["run", "--help"]);
    assert_eq!(run.status.code(), Some(0));
    let run = text(&run.stdout);
    for option in ["--set", "--mcap", "--summary", "--quiet", "SCENARIO", "130"] {
        assert!(run.contains(option), "run --help lacks {option}: {run}");
    }

    let margin = sea_sim(&["margin", "--help"]);
    assert_eq!(margin.status.code(), Some(0));
    let margin = text(&margin.stdout);
    for option in [
        "--param",
        "--range",
        "[default: eigen]",
        "[default: 9]",
        "--out",
        "--json",
    ] {
        assert!(
            margin.contains(option),
            "margin --help lacks {option}: {margin}"
        );
    }

    let bench = sea_sim(&["bench", "--help"]);
    assert_eq!(bench.status.code(), Some(0));
    let bench = text(&bench.stdout);
    for option in [
        "--urdf",
        "--joints",
        "[default: 31]",
        "[default: 2000]",
        "--json",
    ] {
        assert!(
            bench.contains(option),
            "bench --help lacks {option}: {bench}"
        );
    }
}

#[test]
fn bad_command_lines_are_errors() {
    let ws = Workspace::new("args");
    let scenario = ws.scenario();
    let cases: [&[&str]; 5] = [
        &["run", &scenario, &scenario],
        &["run", &scenario, "--frobnicate"],
        &["run"],
        &["run", &scenario, "--set", "no_equals_sign"],
        &["nonsense"],
    ];
    for args in cases {
        let out = sea_sim(args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(text(&out.stderr).contains("error"), "{args:?}");
    }
    let two = text(&sea_sim(&["run", &scenario, &scenario]).stderr);
    assert!(two.contains("unexpected argument"), "{two}");
}

#[test]
fn completed_and_diverged_runs_exit_0_and_3_with_their_outputs() {
    let ws = Workspace::new("status");
    let (mcap, summary_path) = (ws.path("run.mcap"), ws.path("run.json"));
    let out = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        SHORT_RUN,
        "--quiet",
        "--mcap",
        mcap.to_str().unwrap(),
        "--summary",
        summary_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stderr.is_empty(), "--quiet: {}", text(&out.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout JSON");
    assert_eq!(printed, summary(&summary_path));
    assert_eq!(printed["status"], "completed");
    assert!(finished_mcap_messages(&mcap) > 0);
    let leftovers: Vec<_> = std::fs::read_dir(&ws.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    let out = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        SHORT_RUN,
        "--set",
        "simulation.divergence_com_error_m=1e-12",
        "--quiet",
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", text(&out.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout JSON");
    assert_eq!(printed["status"], "diverged");
}

/// A sweep stopped by a signal writes the rows done, counts the run it stopped as not done
/// and exits with the signal's status.
#[test]
fn a_signal_stops_a_sweep_with_the_rows_done_written() {
    let ws = Workspace::new("sweep_signal");
    let csv = ws.path("rows.csv");
    let scenario = ws.scenario();
    let mut sweep = Running::start_command(
        ("sweep", &scenario),
        &[
            "--grid",
            "simulation.duration_s=0.2,300,300",
            "--jobs",
            "1",
            "--out",
            csv.to_str().unwrap(),
        ],
        Stdio::null(),
    );
    sweep.wait_for_line("sweep 1/3");
    // The second run (300 s) builds and starts once the first has ended: signal it under way,
    // not in between (a signal between runs stops the sweep with no run part-way).
    std::thread::sleep(Duration::from_millis(1500));
    sweep.signal("INT");
    let (status, stderr) = sweep.wait();
    assert_eq!(status, Some(130), "{stderr}");
    assert!(
        stderr.contains("1 of 3 runs done, 1 completed, 1 stopped part-way"),
        "{stderr}"
    );
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 3, "a header and two rows: {rows}");
    assert!(rows.contains("interrupted"), "{rows}");
}

#[test]
fn signals_stop_the_run_with_a_finished_log_and_an_interrupted_summary() {
    let ws = Workspace::new("signals");
    for (name, code) in [("INT", 130), ("TERM", 143), ("HUP", 129)] {
        if name == "HUP" && sighup_ignored() {
            // Under `nohup` the run inherits SIGHUP ignored and rightly keeps it so.
            eprintln!("SIGHUP is ignored in this process (nohup?): not tested");
            continue;
        }
        let mcap = ws.path(&format!("{name}.mcap"));
        let summary_path = ws.path(&format!("{name}.json"));
        let mut run = Running::start(
            &ws.scenario(),
            &[
                "--set",
                LONG_RUN,
                "--mcap",
                mcap.to_str().unwrap(),
                "--summary",
                summary_path.to_str().unwrap(),
            ],
        );
        run.wait_for_progress();
        let signalled = Instant::now();
        run.signal(name);
        let (status, stderr) = run.wait();
        assert_eq!(status, Some(code), "SIG{name}: {stderr}");
        assert!(
            signalled.elapsed() < Duration::from_secs(5),
            "SIG{name} stops at the next tick, not after {:?}",
            signalled.elapsed()
        );
        let json = summary(&summary_path);
        assert_eq!(json["status"], "interrupted", "SIG{name}");
        let reached = json["duration_s"].as_f64().unwrap();
        assert!((1.0..300.0).contains(&reached), "time reached {reached}");
        assert!(finished_mcap_messages(&mcap) > 0, "SIG{name}");
    }
}

#[test]
fn a_killed_rerun_leaves_the_earlier_log_untouched_and_its_chunks_recoverable() {
    let ws = Workspace::new("killed");
    let mcap = ws.path("run.mcap");
    let first = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        SHORT_RUN,
        "--quiet",
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    assert_eq!(first.status.code(), Some(0), "{}", text(&first.stderr));
    let good = std::fs::read(&mcap).unwrap();

    let mut rerun = Running::start(
        &ws.scenario(),
        &["--set", LONG_RUN, "--mcap", mcap.to_str().unwrap()],
    );
    rerun.wait_for_progress();
    // The writer flushes a chunk every second of wall time.
    std::thread::sleep(Duration::from_millis(1500));
    rerun.signal("KILL");
    let (status, _) = rerun.wait();
    assert_eq!(status, None, "killed by SIGKILL");
    assert!(
        std::fs::read(&mcap).unwrap() == good,
        "the earlier log is untouched"
    );

    // The partial file beside it holds complete chunks that a reader recovers.
    let partial = std::fs::read(ws.path(".run.mcap.partial")).expect("partial file");
    let recovered = mcap::MessageStream::new(&partial)
        .expect("header")
        .map_while(Result::ok)
        .count();
    assert!(recovered > 0, "no message recovered from the partial file");
}

#[test]
fn a_second_writer_of_the_same_log_is_refused() {
    let ws = Workspace::new("lock");
    let mcap = ws.path("run.mcap");
    let mut first = Running::start(
        &ws.scenario(),
        &["--set", LONG_RUN, "--mcap", mcap.to_str().unwrap()],
    );
    first.wait_for_progress();
    let second = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        SHORT_RUN,
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    let message = text(&second.stderr);
    assert_eq!(second.status.code(), Some(1), "{message}");
    assert!(message.contains("another process is writing"), "{message}");
    assert!(message.contains("run.mcap"), "{message}");

    first.signal("TERM");
    let (status, stderr) = first.wait();
    assert_eq!(status, Some(143), "{stderr}");
    assert!(
        finished_mcap_messages(&mcap) > 0,
        "the first writer's log is intact"
    );
}

#[test]
fn outputs_that_are_inputs_or_each_other_are_refused_before_the_run() {
    let ws = Workspace::new("same");
    let scenario = ws.scenario();
    let before = std::fs::read(&scenario).unwrap();
    let same = ws.path("same");
    let urdf = Path::new(REPO).join("urdf/icub25.urdf");
    let cases: [(&[&str], &str); 3] = [
        (
            &[
                "--mcap",
                same.to_str().unwrap(),
                "--summary",
                same.to_str().unwrap(),
            ],
            "name the same file",
        ),
        (&["--mcap", &scenario], "the scenario file"),
        (&["--summary", urdf.to_str().unwrap()], "the URDF"),
    ];
    for (outputs, expected) in cases {
        let mut args = vec!["run", scenario.as_str(), "--set", LONG_RUN];
        args.extend_from_slice(outputs);
        let started = Instant::now();
        let out = sea_sim(&args);
        let message = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{outputs:?}: {message}");
        assert!(message.contains(expected), "{outputs:?}: {message}");
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "refused before the run"
        );
    }
    assert_eq!(std::fs::read(&scenario).unwrap(), before);
    assert!(!same.exists());
}

/// Every command that writes refuses each of the scenario's input files as its output: the
/// robot description's file and the URDF, in `run`, `sweep` and `margin` alike.
#[test]
fn no_output_overwrites_the_robot_description_or_the_urdf() {
    let ws = Workspace::new("inputs");
    let description = ws.path("desc.toml");
    std::fs::copy(Path::new(REPO).join("robots/icub_paper.toml"), &description).unwrap();
    let urdf = ws.path("robot.urdf");
    std::fs::copy(Path::new(REPO).join("urdf/icub25.urdf"), &urdf).unwrap();
    let text = std::fs::read_to_string(ws.scenario()).unwrap();
    let icub = Path::new(REPO)
        .join("urdf/icub25.urdf")
        .canonicalize()
        .unwrap();
    let text = text.replace(
        &format!("urdf = \"{}\"", icub.display()),
        "urdf = \"robot.urdf\"\ndescription = \"desc.toml\"",
    );
    assert!(text.contains("desc.toml"), "description set");
    std::fs::write(ws.path("described.toml"), text).unwrap();
    let scenario = ws.path("described.toml").display().to_string();
    let (description, urdf) = (
        description.display().to_string(),
        urdf.display().to_string(),
    );
    let before = [&description, &urdf].map(|f| std::fs::read(f).unwrap());
    let margin = [
        "--param",
        "controller.damping_estimate_scale",
        "--range",
        "0.5:1.5",
    ];
    let grid = ["--grid", "controller.damping_estimate_scale=1,2"];
    let cases: [(Vec<&str>, &str); 4] = [
        (
            vec!["run", &scenario, "--summary", &description],
            "the robot description file",
        ),
        (vec!["run", &scenario, "--mcap", &urdf], "the URDF"),
        (
            [&["sweep", &scenario, "--out", &description][..], &grid].concat(),
            "the robot description file",
        ),
        (
            [&["margin", &scenario, "--out", &urdf][..], &margin].concat(),
            "the URDF",
        ),
    ];
    for (args, input) in cases {
        let out = sea_sim(&args);
        let path = args[args.iter().position(|a| a.starts_with("--")).unwrap() + 1];
        assert_refused(&out, path, &format!("would overwrite {input}"));
    }
    let after = [&description, &urdf].map(|f| std::fs::read(f).unwrap());
    assert!(before == after, "the inputs are untouched");
}

/// A doubtful URDF element the model loads anyway (the left elbow's limits inverted, so taken
/// as unlimited) is a warning of `run` naming the URDF and the joint; the run goes on.
#[test]
fn a_run_warns_of_the_urdf_elements_the_model_doubts() {
    let ws = Workspace::new("doubts");
    let elbow = r#"lower="0.2617993877991494" upper="1.8500490071139892""#;
    let urdf = std::fs::read_to_string(Path::new(REPO).join("urdf/icub25.urdf")).unwrap();
    assert!(urdf.contains(elbow), "the elbow's limits");
    let inverted = urdf.replace(elbow, r#"lower="1.85" upper="0.26""#);
    std::fs::write(ws.path("inverted.urdf"), inverted).unwrap();
    let scenario = std::fs::read_to_string(ws.scenario()).unwrap();
    let icub = Path::new(REPO)
        .join("urdf/icub25.urdf")
        .canonicalize()
        .unwrap();
    let scenario = scenario.replace(&icub.display().to_string(), "inverted.urdf");
    std::fs::write(ws.path("inverted.toml"), scenario).unwrap();
    let out = sea_sim(&[
        "run",
        ws.path("inverted.toml").to_str().unwrap(),
        "--set",
        SHORT_RUN,
        "--quiet",
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("warning: ")
            && stderr.contains("inverted.urdf: joint 'l_elbow'")
            && stderr.contains("taken as unlimited"),
        "{stderr}"
    );
    let clean = short_run(&ws, &[]);
    assert!(
        !text(&clean.stderr).contains("warning"),
        "{}",
        text(&clean.stderr)
    );
}

#[test]
fn a_missing_summary_folder_is_refused_before_the_run() {
    let ws = Workspace::new("folder");
    let missing = ws.path("no_such_folder/summary.json");
    let mcap = ws.path("run.mcap");
    let started = Instant::now();
    let out = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        LONG_RUN,
        "--mcap",
        mcap.to_str().unwrap(),
        "--summary",
        missing.to_str().unwrap(),
    ]);
    let message = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(
        message.contains("no_such_folder") && message.contains("does not exist"),
        "{message}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "refused before the run"
    );
    assert!(!mcap.exists() && !ws.path(".run.mcap.partial").exists());
}

#[test]
fn an_unwritable_folder_is_an_error_naming_the_path_given() {
    // /proc exists but takes no new files: the partial file beside the target cannot be
    // created, and the error must name the path the user gave, not only the partial file.
    if !Path::new("/proc").is_dir() {
        eprintln!("no /proc here; skipped");
        return;
    }
    let ws = Workspace::new("unwritable");
    let out = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        SHORT_RUN,
        "--quiet",
        "--mcap",
        "/proc/x.mcap",
    ]);
    let message = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(message.contains("/proc/x.mcap"), "{message}");
}

#[test]
fn a_full_disk_is_an_error_naming_the_file_and_the_cause() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let ws = Workspace::new("full");
    let out = short_run(&ws, &["--summary", "/dev/full"]);
    let message = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(message.contains("/dev/full"), "{message}");
    assert!(message.contains("No space left on device"), "{message}");
    // A log is written with seeks: a device is refused as the run starts, before any step.
    for device in ["/dev/full", "/dev/null"] {
        let out = short_run(&ws, &["--mcap", device]);
        assert_refused(&out, device, "must be a regular file");
    }
    // The run is done when the summary cannot be written: its log is kept, its summary printed.
    let log = ws.path("kept.mcap");
    let out = short_run(
        &ws,
        &["--summary", "/dev/full", "--mcap", log.to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("\"status\": \"completed\""));
    assert!(
        std::fs::metadata(&log).is_ok_and(|m| m.len() > 0),
        "no log kept"
    );
}

#[test]
fn a_sweep_or_margin_whose_out_cannot_be_written_prints_its_results() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let ws = Workspace::new("full_out");
    let scenario = ws.scenario();
    let grid = ["--grid", "actuators.damping=0.5,1", "--set", SHORT_RUN];
    let mut args = vec!["sweep", scenario.as_str(), "--out", "/dev/full", "-q"];
    args.extend_from_slice(&grid);
    let out = sea_sim(&args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("No space left on device"), "{stderr}");
    let rows = text(&out.stdout);
    assert_eq!(rows.lines().count(), 3, "a header and two rows: {rows}");
    assert!(rows.starts_with("actuators.damping,status"), "{rows}");
    let out = sea_sim(&[
        "margin",
        &scenario,
        "--param",
        "actuators.damping",
        "--range",
        "0.5:1",
        "--points",
        "2",
        "--out",
        "/dev/full",
        "--json",
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout JSON");
    assert_eq!(printed["parameter"], "actuators.damping");
}

/// A summary into a FIFO: with no reader the run is refused at once naming it (the open used to
/// wait for a reader forever, deaf to SIGTERM); with one the summary is read from it.
#[cfg(unix)]
#[test]
fn a_summary_into_a_pipe_needs_its_reader() {
    let ws = Workspace::new("fifo");
    let fifo = ws.path("summary.fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|status| status.success()) {
        eprintln!("no mkfifo here; skipped");
        return;
    }
    let fifo_arg = fifo.to_str().unwrap();
    let out = short_run(&ws, &["--summary", fifo_arg]);
    assert_refused(&out, fifo_arg, "with no reader");
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    // The reader opens the FIFO first; the run retries until it has.
    let mut out = short_run(&ws, &["--summary", fifo_arg]);
    for _ in 0..50 {
        if out.status.code() == Some(0) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
        out = short_run(&ws, &["--summary", fifo_arg]);
    }
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let read: serde_json::Value = serde_json::from_str(&reader.join().unwrap()).unwrap();
    assert_eq!(read["status"], "completed");
}

#[test]
fn closed_stdout_and_stderr_do_not_abort_the_run() {
    let ws = Workspace::new("pipes");
    let summary_path = ws.path("run.json");
    let mut child = Command::new(BIN)
        .args(["run", &ws.scenario(), "--set", "simulation.duration_s=2.5"])
        .args(["--summary", summary_path.to_str().unwrap()])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // As `2>&1 | head -c1`: the reader goes away after the first byte.
    let mut stderr = child.stderr.take().unwrap();
    let mut first = [0u8; 1];
    std::io::Read::read_exact(&mut stderr, &mut first).unwrap();
    drop(stderr);
    drop(child.stdout.take());
    let deadline = Instant::now() + TIMEOUT;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "did not finish");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(0));
    assert_eq!(summary(&summary_path)["status"], "completed");
}

/// A report that cannot be written on stdout (redirected to a full disk) is an error: it is the
/// command's product. A file name with a terminal escape is echoed escaped.
#[test]
fn a_full_stdout_is_an_error_and_control_characters_are_echoed_escaped() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let ws = Workspace::new("stdout_full");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = Command::new(BIN)
        .args(["run", &ws.scenario(), "--set", SHORT_RUN, "--quiet"])
        .stdout(full)
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("stdout: No space left on device"),
        "{stderr}"
    );
    let out = sea_sim(&["run", "no_such\u{1b}[31m.toml"]);
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("no_such\\u{1b}[31m.toml") && !stderr.contains('\u{1b}'),
        "{stderr:?}"
    );
}

/// A tiny tmpfs mounted on a folder, unmounted on drop; `None` where mounting is not allowed.
struct TinyFileSystem(PathBuf);

impl TinyFileSystem {
    fn mount(dir: PathBuf, size: &str) -> Option<Self> {
        std::fs::create_dir_all(&dir).ok()?;
        let mounted = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(&dir)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        mounted.then_some(Self(dir))
    }
}

impl Drop for TinyFileSystem {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

#[test]
fn a_full_file_system_keeps_the_earlier_log_and_names_the_file() {
    let ws = Workspace::new("tmpfs");
    let Some(fs) = TinyFileSystem::mount(ws.path("tiny"), "256k") else {
        eprintln!("cannot mount a tmpfs here; skipped (/dev/full is tested above)");
        return;
    };
    let mcap = fs.0.join("run.mcap");
    let earlier = b"an earlier log the run must not destroy".repeat(100);
    std::fs::write(&mcap, &earlier).unwrap();
    let out = sea_sim(&[
        "run",
        &ws.scenario(),
        "--set",
        "simulation.duration_s=5",
        "--quiet",
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    let message = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(message.contains(mcap.to_str().unwrap()), "{message}");
    assert!(message.contains("No space left on device"), "{message}");
    assert_eq!(std::fs::read(&mcap).unwrap(), earlier);
    assert!(
        !fs.0.join(".run.mcap.partial").exists(),
        "the partial file is removed"
    );
}

#[test]
fn margin_reports_the_damping_boundary_as_json() {
    let ws = Workspace::new("margin");
    let out_path = ws.path("margin.json");
    let scenario = ws.scenario();
    // `sea-sim margin` of the damping over `range`, with `extra` flags.
    let damping_margin = |range: &str, extra: &[&str]| {
        let mut args = vec![
            "margin",
            scenario.as_str(),
            "--param",
            "actuators.damping",
            "--range",
            range,
        ];
        args.extend_from_slice(extra);
        sea_sim(&args)
    };
    let out = damping_margin(
        "0.01:1",
        &[
            "--points",
            "3",
            "--tolerance",
            "0.1",
            "--out",
            out_path.to_str().unwrap(),
            "--json",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout JSON");
    assert_eq!(printed, summary(&out_path), "--out holds what was printed");
    let samples = printed["samples"].as_array().unwrap();
    assert_eq!(printed["evaluations"].as_u64(), Some(samples.len() as u64));
    // A progress line per evaluation.
    let stderr = text(&out.stderr);
    let progress = stderr
        .lines()
        .filter(|l| l.starts_with("sea-sim: margin actuators.damping = "));
    assert_eq!(progress.count(), samples.len(), "{stderr}");
    assert!(
        stderr.contains("actuators.damping = 0.01: unstable (growth "),
        "{stderr}"
    );
    assert_eq!(printed["interrupted"], false);
    // The feet welded: every linearisation is about an equilibrium.
    assert_eq!(printed["evaluations_without_equilibrium"].as_u64(), Some(0));
    assert!(samples
        .iter()
        .all(|s| s["no_equilibrium_residual"].is_null()));
    assert_eq!(
        printed["boundaries_beside_no_equilibrium"],
        serde_json::json!([])
    );
    // Unstable at the low end of the scan, stable at the high end: one boundary between.
    assert_eq!(samples[0]["stable"], false);
    assert_eq!(samples[2]["stable"], true);
    let boundaries = printed["boundaries"].as_array().unwrap();
    assert_eq!(boundaries.len(), 1, "{printed}");
    let boundary = boundaries[0].as_f64().unwrap();
    assert!((0.01..0.505).contains(&boundary), "{boundary}");

    // Without --json: a table naming the parameter and the boundary.
    let table = damping_margin("0.01:1", &["--points", "2", "--tolerance", "0.5"]);
    assert_eq!(table.status.code(), Some(0), "{}", text(&table.stderr));
    let table = text(&table.stdout);
    assert!(
        table.starts_with("actuators.damping (eigen method") && table.contains("unstable"),
        "{table}"
    );

    // On the compliant ground a sole creeps and Newton finds no equilibrium: each evaluation,
    // the JSON and the verdict say so.
    let ground_json = ws.path("ground.json");
    let ground = damping_margin(
        "0.5:1",
        &[
            "--points",
            "2",
            "--set",
            "plant.contact_model=unilateral",
            "--out",
            ground_json.to_str().unwrap(),
        ],
    );
    assert_eq!(ground.status.code(), Some(0), "{}", text(&ground.stderr));
    let (table, stderr) = (text(&ground.stdout), text(&ground.stderr));
    assert!(
        stderr.contains("1/s; no equilibrium found (residual "),
        "{stderr}"
    );
    assert!(
        table.contains("but at 2 of 2 evaluations Newton's method found no equilibrium")
            && table.contains("--set plant.contact_model=bilateral"),
        "{table}"
    );
    let report = summary(&ground_json);
    assert_eq!(report["evaluations_without_equilibrium"].as_u64(), Some(2));
    for sample in report["samples"].as_array().unwrap() {
        let residual = sample["no_equilibrium_residual"].as_f64().unwrap();
        assert!(residual > 1e-3, "{sample}");
    }

    // An [actuators] key's own value, as the file and --set give it, is evaluated too.
    let given = damping_margin(
        "0.5:1",
        &["--points", "2", "--set", "actuators.damping=0.75", "--json"],
    );
    assert_eq!(given.status.code(), Some(0), "{}", text(&given.stderr));
    let given: serde_json::Value = serde_json::from_slice(&given.stdout).expect("stdout JSON");
    assert_eq!(given["own_value"].as_f64(), Some(0.75), "{given}");
    assert_eq!(given["evaluations"].as_u64(), Some(3), "{given}");
    assert_eq!(given["growth_unchanged"], false, "{given}");

    // A walking key: its own value as parsed, and the linearisation about the standing
    // equilibrium leaves it out, which the verdict says.
    let walk = format!("{REPO}/scenarios/walking/walk_straight.toml");
    let walking = sea_sim(&[
        "margin",
        &walk,
        "--param",
        "walking.com_height",
        "--range",
        "0.4:0.6",
        "--points",
        "3",
        "-q",
    ]);
    let verdict = text(&walking.stdout);
    assert_eq!(walking.status.code(), Some(0), "{}", text(&walking.stderr));
    assert!(
        verdict.contains("own value 0.53 ")
            && verdict.contains("walking.com_height does not enter the linearisation"),
        "{verdict}"
    );

    let bad = sea_sim(&["margin", &ws.scenario(), "--param", "x", "--range", "1"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(text(&bad.stderr).contains("LOWER:UPPER"));
}

/// Whether this process ignores SIGHUP (as under `nohup`), from `SigIgn` in
/// `/proc/self/status` (bit 0 is signal 1); `false` where that file does not exist.
fn sighup_ignored() -> bool {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("SigIgn:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| mask & 1 == 1)
}

#[test]
fn package_dir_finds_the_meshes_a_run_warns_about_without_it() {
    let ws = Workspace::new("package_dir");
    let packages = ws.path("packages");
    std::fs::create_dir_all(packages.join("my_pkg/meshes")).unwrap();
    let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\nendsolid t\n";
    std::fs::write(packages.join("my_pkg/meshes/part.stl"), stl).unwrap();
    // icub25 with a mesh on root_link, after its own visual, in a folder beside `packages`.
    let icub = std::fs::read_to_string(format!("{REPO}/urdf/icub25.urdf")).unwrap();
    let (head, tail) = icub.split_once("<link name=\"root_link\">").unwrap();
    let (root, rest) = tail.split_once("</link>").unwrap();
    let mesh = r#"<visual><geometry><mesh filename="package://my_pkg/meshes/part.stl"/></geometry></visual>"#;
    std::fs::create_dir_all(ws.path("robot")).unwrap();
    let urdf = ws.path("robot/icub_mesh.urdf");
    std::fs::write(
        &urdf,
        format!("{head}<link name=\"root_link\">{root}{mesh}</link>{rest}"),
    )
    .unwrap();
    let set_urdf = format!("robot.urdf={}", urdf.display());
    let scenario = ws.scenario();
    let run = |extra: &[&str]| {
        let mcap = ws.path("run.mcap");
        let mut args = vec!["run", &scenario, "--set", SHORT_RUN, "--set", &set_urdf];
        args.extend(["--quiet", "--mcap", mcap.to_str().unwrap()]);
        args.extend(extra);
        let out = sea_sim(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        assert!(finished_mcap_messages(&mcap) > 0);
        text(&out.stderr)
    };
    let warned = run(&[]);
    assert!(warned.contains("warning:"), "{warned}");
    assert!(warned.contains("link 'root_link'"), "{warned}");
    assert!(
        warned.contains("package://my_pkg/meshes/part.stl"),
        "{warned}"
    );
    let found = run(&["--package-dir", packages.to_str().unwrap()]);
    assert!(found.is_empty(), "{found}");
}

#[test]
fn push_refuses_a_zero_tolerance_or_duration_naming_the_flag() {
    let scenario = format!("{REPO}/scenarios/robot_rate/push_two_feet.toml");
    for (flag, value) in [
        ("--tolerance", "0"),
        ("--duration", "0"),
        ("--duration", "inf"),
    ] {
        let output = sea_sim(&["push", &scenario, flag, value]);
        assert!(!output.status.success(), "{flag} {value} accepted");
        let stderr = text(&output.stderr);
        assert!(stderr.contains(flag), "{flag} {value}: {stderr}");
        assert!(
            stderr.contains("finite, positive"),
            "{flag} {value}: {stderr}"
        );
    }
}

#[test]
fn push_refuses_a_bad_start_link_or_direction_naming_the_flag() {
    let scenario = format!("{REPO}/scenarios/robot_rate/push_two_feet.toml");
    for value in ["-1", "inf", "nan"] {
        let output = sea_sim(&["push", &scenario, &format!("--start={value}")]);
        assert!(!output.status.success(), "--start {value} accepted");
        let stderr = text(&output.stderr);
        assert!(
            stderr.contains("--start") && stderr.contains("finite, non-negative"),
            "--start {value}: {stderr}"
        );
    }
    // A push after the run's end would be recovered at any size.
    let output = sea_sim(&["push", &scenario, "--start", "10"]);
    let stderr = text(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("--start") && stderr.contains("within the run"),
        "--start 10 on a 3 s run: {stderr}"
    );
    // A length off the plant's steps is named as the flag, with the value given.
    let output = sea_sim(&["push", &scenario, "--duration", "0.0001"]);
    let stderr = text(&output.stderr);
    assert!(
        !output.status.success()
            && stderr.contains("--duration")
            && stderr.contains("whole number of plant steps")
            && stderr.contains("0.0001")
            && !stderr.contains("disturbances"),
        "--duration 0.0001: {stderr}"
    );
    let output = sea_sim(&["push", &scenario, "--link", "no_such_link"]);
    assert!(!output.status.success(), "--link no_such_link accepted");
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("--link")
            && stderr.contains("no_such_link")
            && !stderr.contains("disturbances"),
        "--link: {stderr}"
    );
    // Also while walking, where the swing's timing takes a run first: the flag comes first.
    let walk = format!("{REPO}/scenarios/walking/walk_push.toml");
    let output = sea_sim(&["push", &walk, "--phase", "0.5", "--link", "no_such_link"]);
    let stderr = text(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("--link") && stderr.contains("no_such_link"),
        "--link while walking: {stderr}"
    );
    let output = sea_sim(&["push", &scenario, "--directions", "forward,up"]);
    assert!(!output.status.success(), "direction 'up' accepted");
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("'up'") && stderr.contains("--directions") && stderr.contains("left"),
        "{stderr}"
    );
    let output = sea_sim(&["push", &scenario, "--directions", "left,right,left"]);
    let stderr = text(&output.stderr);
    assert!(
        output.status.code() == Some(1)
            && stderr.contains("--directions")
            && stderr.contains("'left' given twice"),
        "a direction twice: {stderr}"
    );
}

#[test]
fn push_at_fixed_impulses_reports_each_outcome_and_refuses_a_negative_one() {
    let scenario = format!("{REPO}/scenarios/robot_rate/push_two_feet.toml");
    let refused = sea_sim(&["push", &scenario, "--impulses=1,-2"]);
    assert!(!refused.status.success(), "a negative impulse accepted");
    let stderr = text(&refused.stderr);
    assert!(stderr.contains("impulses"), "{stderr}");
    // No push, and eight times the backward capture-point bound (7.7 N s).
    let args = [
        "push",
        &scenario,
        "--directions",
        "backward",
        "--impulses",
        "0,60",
    ];
    let out = sea_sim(&[&args[..], &["--set", "simulation.duration_s=2.0"]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let row = &report["directions"][0];
    assert_eq!(row["direction"], "backward");
    assert_eq!(row["outcomes"], "ox", "{row}");
    assert_eq!(row["recovered_count"], 1);
    assert_eq!(row["recovered_up_to_n_s"], 0.0);
    let pushes = row["pushes"].as_array().unwrap();
    assert_eq!(pushes[0]["status"], "completed");
    assert_ne!(pushes[1]["status"], "completed");
    assert!(pushes[1]["end_s"].as_f64().unwrap() < 2.0, "{row}");
    // One progress line per run as it ends (in either order), none with --quiet.
    let stderr = text(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.contains(": push ")).collect();
    assert_eq!(lines.len(), 2, "{stderr}");
    assert!(
        lines.contains(&"sea-sim: push backward 0 N s: completed"),
        "{stderr}"
    );
    let failed = lines
        .iter()
        .find(|l| l.contains("backward 60 N s"))
        .unwrap();
    assert!(
        failed.contains(" at ") && !failed.contains("completed"),
        "{stderr}"
    );
    let short = [
        "--set",
        "simulation.duration_s=0.01",
        "--start",
        "0",
        "--duration",
        "0.005",
    ];
    // Quiet: no progress; the warning that the run ends too soon after the push stays.
    let quiet = sea_sim(&[&args[..], &short[..], &["-q"]].concat());
    let stderr = text(&quiet.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    assert!(quiet.status.success() && lines.len() == 1, "{stderr}");
    assert!(
        lines[0].starts_with("sea-sim: warning: the run ends 0.005 s after the push"),
        "{stderr}"
    );
}

#[test]
fn push_reports_the_stepping_bound_on_a_stepping_scenario_and_the_gaits_pushing_a_walk() {
    // The bounds need no run: unpushed runs that end soon after the push (the walk's at 20 %
    // of the fourth swing, 1.9 s).
    let short = ["--impulses", "0", "--set", "simulation.duration_s=2.1"];
    let stepping = format!("{REPO}/scenarios/walking/push_recovery_step.toml");
    let args = ["push", &stepping, "--directions", "forward,left"];
    let out = sea_sim(&[&args[..], &short[..]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let [forward, left] = [&report["directions"][0], &report["directions"][1]];
    assert_eq!(forward["stepping_bound"]["first_step"]["lift_off_s"], 0.0);
    assert!(
        forward["stepping_bound"]["impulse_n_s"].as_f64().unwrap() > 20.0,
        "{forward}"
    );
    assert!(left["stepping_bound"]["first_step"].is_null(), "{left}");
    assert!(forward.get("gait_bound_impulse_n_s").is_none(), "{forward}");
    let walk = format!("{REPO}/scenarios/walking/walk_push.toml");
    let args = [
        "push",
        &walk,
        "--phase",
        "0.2",
        "--directions",
        "forward,right",
    ];
    let out = sea_sim(&[&args[..], &short[..]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let [forward, right] = [&report["directions"][0], &report["directions"][1]];
    assert!(forward["gait_bound_impulse_n_s"].is_null(), "{forward}");
    let bound = right["gait_bound_impulse_n_s"].as_f64().unwrap();
    assert!((bound - 13.67).abs() < 0.05, "{right}");
    // walk_push.toml does not adjust its steps: every landing where the plan puts it.
    let planned = right["adjustment_bound_impulse_n_s"].as_f64().unwrap();
    assert!(planned < bound, "{right}");
    assert!(
        forward["adjustment_bound_impulse_n_s"].is_null(),
        "{forward}"
    );
    assert!(right.get("stepping_bound").is_none(), "{right}");
    // A scenario that does not step has no stepping bound.
    let standing = format!("{REPO}/scenarios/robot_rate/push_two_feet.toml");
    let out = sea_sim(&[&["push", &standing, "--directions", "left"][..], &short[..]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["directions"][0].get("stepping_bound").is_none());
}

#[test]
fn a_walking_command_the_step_limits_clip_is_a_warning_naming_the_key() {
    let walk = format!("{REPO}/scenarios/walking/walk_straight.toml");
    let short = ["--set", "simulation.duration_s=0.02", "--quiet"];
    let run = |extra: &[&str]| sea_sim(&[&["run", &walk][..], &short[..], extra].concat());
    let out = run(&["--set", "walking.command.forward_velocity=1.0"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    let warning = stderr
        .lines()
        .find(|line| line.starts_with("warning: walking.command.forward_velocity = 1 m/s"))
        .unwrap_or_else(|| panic!("no warning in {stderr}"));
    assert!(
        warning.contains("walking.max_step_length allows"),
        "{warning}"
    );
    // The scenario's own command is within the limits: no warning.
    let out = run(&[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        !text(&out.stderr).contains("warning"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn unbounded_study_sizes_are_refused_naming_the_flag() {
    let ws = Workspace::new("bounds");
    let margin = |range: &str, flag: &str, value: &str| {
        let scenario = ws.scenario();
        let param = ["--param", "actuators.damping"];
        sea_sim(
            &[
                &["margin", &scenario],
                &param[..],
                &["--range", range, flag, value],
            ]
            .concat(),
        )
    };
    for (flag, value) in [
        ("--tolerance", "0"),
        ("--tolerance", "nan"),
        ("--points", "4000000000"),
    ] {
        let out = margin("0.01:1", flag, value);
        assert_ne!(out.status.code(), Some(0), "{flag} {value}");
        assert!(text(&out.stderr).contains(flag), "{}", text(&out.stderr));
    }
    for range in ["1:0.5", "-1:-2"] {
        let out = margin(range, "--points", "3");
        let message = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{message}");
        assert!(
            message.contains("--range:") && !message.contains("scenario key"),
            "{message}"
        );
    }
    let urdf = format!("{REPO}/urdf/icub25.urdf");
    let out_file = ws.path("init.toml");
    let init = |urdf: &str, foot: &str| {
        let out_file = out_file.to_str().unwrap();
        let contacts = ["--contacts", "l_sole", "r_sole"];
        sea_sim(
            &[
                &["init", urdf],
                &contacts[..],
                &["--foot", foot, "--out", out_file],
            ]
            .concat(),
        )
    };
    for (urdf, foot, named) in [
        (
            urdf.as_str(),
            "0.1,0.1,-0.05,0.05",
            "--foot: expected x0 < x1",
        ),
        (urdf.as_str(), "1,2,3", "--foot: expected four"),
        (
            "no_such.urdf",
            "-0.05,0.1,-0.03,0.03",
            "URDF: expected a URDF that can be found",
        ),
    ] {
        let out = init(urdf, foot);
        let message = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{message}");
        assert!(message.contains(named), "{message}");
    }
    assert!(!out_file.exists());
    let csv = ws.path("rows.csv");
    let out = sea_sim(&[
        "sweep",
        &ws.scenario(),
        "--grid",
        "actuators.damping=0.1:1:1000000000",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("COUNT"), "{}", text(&out.stderr));
    let out = sea_sim(&["run", &ws.scenario(), "--set", "robot.urdf=\"/dev/zero\""]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("/dev/zero: not a regular file"),
        "{}",
        text(&out.stderr)
    );
}
