"""Ctrl-C in Python (issue 10, item 1): a real SIGINT sent to a real interpreter running
``run_scenario`` or ``Plant.simulate`` raises ``KeyboardInterrupt`` within a fraction of a
second, the MCAP log is finished (readable, with its summary section) and what was computed is
the exception's ``partial`` attribute, with status "interrupted". SIGTERM (a scheduler's stop)
does the same with ``SystemExit(143)`` while the native work runs, and the interpreter's own
disposition of SIGTERM is back afterwards."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
BIPED = ROOT / "urdf" / "mini_biped.urdf"

#: From SIGINT to the KeyboardInterrupt in the child: the binding polls signals every 50 ms and
#: the native loop stops at its next sample; the rest is margin for a loaded 2-core machine.
REACTION_LIMIT_S = 1.0

PRELUDE = """
import json, sys, time
import numpy as np
import sea_momentum as sm

def report(**fields):
    print(json.dumps(fields), flush=True)
"""

RUN_SCENARIO = """
report(event="started")
try:
    sm.run_scenario(sys.argv[1], {"simulation.duration_s": 600.0}, mcap=sys.argv[2])
    report(event="returned")
except KeyboardInterrupt as interrupt:
    caught = time.monotonic()
    partial = interrupt.partial
    report(event="interrupted", caught=caught, status=partial.status,
           rows=len(partial.time), last_time=float(partial.time[-1]),
           summary_duration=partial.summary.duration_s,
           finite=bool(np.all(np.isfinite(partial.q))))
"""

SIMULATE = """
model = sm.Model.from_urdf(sys.argv[1])
plant = sm.Plant(model, actuator="elastic", gravity=(0.0, 0.0, 0.0))
x0 = plant.make_state(model.neutral())
report(event="started")
try:
    plant.simulate(x0, np.zeros(model.n_joints), 1e-4, 10**9, record_every=10**6)
    report(event="returned")
except KeyboardInterrupt as interrupt:
    caught = time.monotonic()
    partial = interrupt.partial
    report(event="interrupted", caught=caught, status=partial.status,
           rows=len(partial.time), last_time=float(partial.time[-1]),
           shape=list(partial.x.shape))
"""


RUN_SCENARIO_TERMINATED = """
import signal
report(event="started")
try:
    sm.run_scenario(sys.argv[1], {"simulation.duration_s": 600.0}, mcap=sys.argv[2])
    report(event="returned")
except SystemExit as stop:
    report(event="terminated", code=stop.code, status=stop.partial.status,
           default_back=signal.getsignal(signal.SIGTERM) == signal.SIG_DFL)
    raise
"""


def interrupt_child(
    body: str, *args: str, run_for_s: float = 2.0, sig: int = signal.SIGINT, status: int = 0
) -> tuple[dict, float]:
    """Runs ``body`` in a fresh interpreter, sends ``sig`` ``run_for_s`` after it reports it
    started, checks that it exits with ``status`` and returns its last report and the time of
    the signal (time.monotonic)."""
    child = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(PRELUDE + body), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
    )
    try:
        started = json.loads(child.stdout.readline() or "{}")
        assert started.get("event") == "started", child.stderr.read()
        time.sleep(run_for_s)
        assert child.poll() is None, "the child ended before the signal"
        sent = time.monotonic()
        child.send_signal(sig)
        out, err = child.communicate(timeout=30)
        assert child.returncode == status, (child.returncode, err)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert lines, f"no report; stderr:\n{err}"
    assert "PanicException" not in err, err
    return lines[-1], sent


def test_ctrl_c_stops_run_scenario_and_finishes_the_log(tmp_path):
    mcap_path = tmp_path / "run.mcap"
    report, sent = interrupt_child(RUN_SCENARIO, str(TRACKING), str(mcap_path))
    assert report["event"] == "interrupted", report
    assert report["caught"] - sent < REACTION_LIMIT_S, report["caught"] - sent
    assert report["status"] == "interrupted"
    assert report["finite"]
    # Samples up to the interrupt are kept, and the summary says how far the run got.
    assert report["rows"] >= 2 and 0.0 < report["last_time"] < 600.0
    assert report["summary_duration"] == pytest.approx(report["last_time"], abs=0.011)
    mcap = pytest.importorskip("mcap.reader")
    with open(mcap_path, "rb") as stream:
        summary = mcap.make_reader(stream).get_summary()
    assert summary is not None and summary.statistics.message_count > 0


def test_ctrl_c_stops_plant_simulate_with_its_partial_result():
    report, sent = interrupt_child(SIMULATE, str(BIPED), run_for_s=1.0)
    assert report["event"] == "interrupted", report
    assert report["caught"] - sent < REACTION_LIMIT_S, report["caught"] - sent
    assert report["status"] == "interrupted"
    # The initial state and the state reached at the interrupt.
    assert report["rows"] >= 2 and report["last_time"] > 0.0
    assert report["shape"][0] == report["rows"]


def test_sigterm_stops_run_scenario_as_an_exit_and_finishes_the_log(tmp_path):
    mcap_path = tmp_path / "run.mcap"
    report, _ = interrupt_child(
        RUN_SCENARIO_TERMINATED, str(TRACKING), str(mcap_path), sig=signal.SIGTERM, status=143
    )
    assert report == {"event": "terminated", "code": 143, "status": "interrupted", "default_back": True}
    mcap = pytest.importorskip("mcap.reader")
    with open(mcap_path, "rb") as stream:
        summary = mcap.make_reader(stream).get_summary()
    assert summary is not None and summary.statistics.message_count > 0


def test_a_sigterm_handler_of_the_program_is_left_alone():
    code = PRELUDE + textwrap.dedent("""
        import signal
        def mine(signum, frame):
            pass
        signal.signal(signal.SIGTERM, mine)
        sm.run_scenario(sys.argv[1], {"simulation.duration_s": 0.05})
        report(kept=signal.getsignal(signal.SIGTERM) is mine)
    """)
    out = subprocess.run([sys.executable, "-c", code, str(TRACKING)], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout.splitlines()[-1]) == {"kept": True}


STABILITY_MARGIN = """
report(event="started")
try:
    # The scanned key is the run's length: the 600 s run is stopped part-way.
    sm.stability_margin(sys.argv[1], "simulation.duration_s", 0.2, 600.0, method="simulate",
                        grid_points=2, overrides={"simulation.duration_s": 0.3})
    report(event="returned")
except KeyboardInterrupt:
    report(event="interrupted", caught=time.monotonic())
"""


def test_ctrl_c_stops_a_simulated_stability_margin():
    report, sent = interrupt_child(STABILITY_MARGIN, str(TRACKING), run_for_s=2.0)
    assert report["event"] == "interrupted", report
    assert report["caught"] - sent < REACTION_LIMIT_S, report["caught"] - sent


def large_stl(path: Path, triangles: int) -> None:
    """A binary STL of ``triangles`` random triangles within 5 cm."""
    import numpy as np

    record = np.dtype([("normal", "<f4", 3), ("vertices", "<f4", 9), ("attribute", "<u2")])
    faces = np.zeros(triangles, dtype=record)
    faces["vertices"] = np.random.default_rng(0).random((triangles, 9), dtype=np.float32) * 0.05
    with open(path, "wb") as stream:
        stream.write(b"\0" * 80)
        stream.write(np.uint32(triangles).tobytes())
        faces.tofile(stream)


def test_ctrl_c_while_a_large_mesh_is_read_stops_the_run_at_once(tmp_path):
    # A 60 MB mesh takes seconds to read and decimate, and its reader cannot be interrupted:
    # the run gives the scene up (no robot drawn, no URDF attached) instead of waiting for it.
    # The signal comes 1 s in: after the build (a signal there raises no partial result),
    # before the mesh is read (3 s on a 2-core EPYC).
    mesh = tmp_path / "large.stl"
    large_stl(mesh, 1_200_000)
    urdf = tmp_path / "icub_large_mesh.urdf"
    text = (ROOT / "urdf" / "icub25.urdf").read_text()
    first_box = '<box size="0.1916 0.1527 0.0980" />'
    assert first_box in text
    urdf.write_text(text.replace(first_box, f'<mesh filename="{mesh}"/>', 1))
    mcap_path = tmp_path / "run.mcap"
    body = RUN_SCENARIO.replace(
        '{"simulation.duration_s": 600.0}',
        '{"simulation.duration_s": 600.0, "robot.urdf": sys.argv[3]}',
    )
    report, sent = interrupt_child(body, str(TRACKING), str(mcap_path), str(urdf), run_for_s=1.0)
    assert report["event"] == "interrupted", report
    assert report["caught"] - sent < REACTION_LIMIT_S, report["caught"] - sent
    assert report["status"] == "interrupted"
    mcap = pytest.importorskip("mcap.reader")
    with open(mcap_path, "rb") as stream:
        summary = mcap.make_reader(stream).get_summary()
    assert summary is not None and summary.statistics.message_count > 0
    assert not summary.attachment_indexes, "the scene was read, not given up"


def test_an_interrupt_before_the_run_began_has_no_partial_result(monkeypatch):
    # Ctrl-C while the scenario is built (before any sample) raises KeyboardInterrupt with no
    # result: `interrupt.partial` is None, so the documented idiom does not fail on it.
    import sea_momentum as sm
    import sea_momentum.scenario as scenario_module

    def interrupted_in_build(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(scenario_module, "run_scenario_native", interrupted_in_build)
    with pytest.raises(KeyboardInterrupt) as interrupt:
        sm.run_scenario(TRACKING)
    assert interrupt.value.partial is None
