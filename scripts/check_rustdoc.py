#!/usr/bin/env python3
"""Builds the workspace's API docs (`cargo doc --workspace --no-deps`) and fails on any rustdoc
warning except a unit in brackets.

The doc comments write units in brackets ("the step duration [s]"): the scenario reference
(`sea_scenario::reference`) reads a key's unit from them, and rustdoc, which takes `[s]` for an
intra-doc link it cannot resolve, warns about each. Every other warning (a broken or private
link, an ambiguous one, a bad code block) fails the check with its location.

Run from the repository root with cargo on PATH: `python3 scripts/check_rustdoc.py`.
"""

import re
import subprocess
import sys

# The units the doc comments write in brackets; a new one is added here.
UNITS = {
    "deg", "Hz", "J", "kg", "m", "ms", "N", "Nm", "ns", "rad", "s", "us", "W",
}

WARNING = re.compile(r"^warning: (.*)$")
UNIT_LINK = re.compile(r"^unresolved link to `([^`]+)`$")
SUMMARY = re.compile(r"^`\S+` \(lib doc\) generated \d+ warnings?")


def warnings_of(log: str) -> list[tuple[str, str]]:
    """(message, location) of every rustdoc warning in cargo's output."""
    found = []
    lines = log.splitlines()
    for i, line in enumerate(lines):
        match = WARNING.match(line)
        if not match or SUMMARY.match(match.group(1)):
            continue
        location = next(
            (l.split("--> ", 1)[1] for l in lines[i + 1 : i + 4] if "--> " in l), "?"
        )
        found.append((match.group(1), location))
    return found


def is_unit(message: str) -> bool:
    """A warning about a bracketed unit (`[m]`), which the doc convention allows."""
    match = UNIT_LINK.match(message)
    return bool(match) and match.group(1) in UNITS


def main() -> int:
    run = subprocess.run(
        ["cargo", "doc", "--workspace", "--no-deps", "--release"],
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        print("check_rustdoc: cargo doc failed", file=sys.stderr)
        return 1
    found = warnings_of(run.stderr)
    bad = [(m, loc) for m, loc in found if not is_unit(m)]
    for message, location in bad:
        print(f"{location}: {message}", file=sys.stderr)
    units = len(found) - len(bad)
    if bad:
        print(
            f"check_rustdoc: {len(bad)} rustdoc warnings ({units} bracketed units allowed)",
            file=sys.stderr,
        )
        return 1
    print(f"check_rustdoc: no rustdoc warnings but {units} bracketed units")
    return 0


if __name__ == "__main__":
    sys.exit(main())
