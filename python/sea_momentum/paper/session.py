"""The application's session: where the scenarios are, where the outputs go, the runs' common
overrides, and the progress lines on stderr."""

from __future__ import annotations

import dataclasses
import pathlib
import sys
import time as clock
from typing import Any, Mapping

from ..scenario import ScenarioResult, run_scenario


def log(message: str) -> None:
    """A progress line on stderr."""
    print(message, file=sys.stderr, flush=True)


def stable(result: Any) -> bool:
    """Whether a run completed (anything with a ``status``)."""
    return bool(result.status == "completed")


def outcome(result: ScenarioResult) -> str:
    """``completed``, ``diverged at T s`` or ``fell at T s``."""
    s = result.summary
    at = s.diverged_at_s if s.fell_at_s is None else s.fell_at_s
    return s.status + ("" if at is None else f" at {at:.2f} s")


@dataclasses.dataclass
class Session:
    """Where the scenarios are, where the outputs go, and the runs' common overrides."""

    scenario_dir: pathlib.Path
    out: pathlib.Path
    duration: float | None
    started: float = dataclasses.field(default_factory=clock.perf_counter)

    def path(self, name: str) -> pathlib.Path:
        """The scenario file ``name`` (without ``.toml``)."""
        return self.scenario_dir / f"{name}.toml"

    def say(self, message: str) -> None:
        """A progress line with the time since the session started."""
        log(f"[{clock.perf_counter() - self.started:6.1f} s] {message}")

    def run(self, name: str, overrides: Mapping[str, Any] | None = None, mcap: str | None = None) -> ScenarioResult:
        """One scenario run; ``duration`` (if given) overrides every run's length."""
        merged = {**(overrides or {})}
        if self.duration is not None:
            merged["simulation.duration_s"] = self.duration
        self.say(f"{name} {merged or ''}")
        result = run_scenario(self.path(name), merged, mcap=None if mcap is None else self.out / mcap)
        s = result.summary
        log(f"          -> {outcome(result)} ({s.sampling}, CoM error rms {s.com_error_rms_m * 1e3:.2f} mm)")
        return result
