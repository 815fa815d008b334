"""A run logged for Foxglove: the robot, its contact points and the push, in one MCAP file.

Runs ``scenarios/robot_rate/push_two_feet.toml`` (the iCub pushed on the pelvis at 1 s, on the
ground) with an MCAP log, lists the log's channels and message counts (read back with the
``mcap`` package when it is installed), and draws the feet's contact points and their forces
at the push. Open the log in the Foxglove app (File > Open, or drag it in) with the layout
``foxglove/layout.json``; ``sea-sim run --live`` serves a run to it as it runs.

Run: ``python examples/foxglove_log.py`` (``--quick``: 2 s instead of 3 s).
"""

from __future__ import annotations

from collections import Counter

import matplotlib

matplotlib.use("Agg")

import sea_momentum as sm  # noqa: E402
from _common import ROOT, SCENARIOS, arguments  # noqa: E402
from sea_momentum import contact_pictures  # noqa: E402


def channel_counts(path) -> Counter | None:
    """Messages per topic of the MCAP file, or None without the ``mcap`` package."""
    try:
        from mcap.reader import make_reader
    except ImportError:
        return None
    with open(path, "rb") as stream:
        return Counter(channel.topic for _, channel, _ in make_reader(stream).iter_messages())


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    log = args.out / "push_two_feet.mcap"
    duration = 2.0 if args.quick else 3.0
    result = sm.run_scenario(SCENARIOS / "robot_rate" / "push_two_feet.toml",
                             {"simulation.duration_s": duration}, mcap=log)
    print(f"run: {result.status}; log: {log} ({log.stat().st_size / 1e6:.1f} MB)")
    counts = channel_counts(log)
    if counts is None:
        print("(pip install mcap to list the log's channels)")
    else:
        for topic, count in sorted(counts.items()):
            print(f"  {topic:32s} {count:6d} messages")
    picture = contact_pictures.contact_points_picture(result, args.out / "foxglove_contacts.png",
                                                      instant=1.05)
    print(f"figure: {picture}")
    layout = ROOT / "foxglove" / "layout.json"
    print(f"Foxglove: open {log}" + (f" with the layout {layout}" if layout.exists() else ""))


if __name__ == "__main__":
    main()
