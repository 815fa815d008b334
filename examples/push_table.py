"""The largest push the robot recovers in four directions, bisected from Python.

``scenarios/robot_rate/push_two_feet.toml``: the iCub on two feet on the ground (unilateral
contacts), the robot-rate design, pushed on the pelvis (``root_link``) for 0.1 s at 1 s. Each
direction's largest recovered force is bisected by running the scenario with its
``disturbances`` replaced (an override of the whole array of tables); a run recovers when it
completes (no fall, no divergence). ``sea-sim push`` does the same from the command line, and
``sm.push_table`` natively from Python (directions in parallel); this example shows the
bisection written out over ``run_scenario``.
Prints the table (force, impulse) and draws it.

Run: ``python examples/push_table.py`` (``--quick``: a coarser bisection).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import SCENARIOS, arguments, save  # noqa: E402

SCENARIO = SCENARIOS / "robot_rate" / "push_two_feet.toml"
DIRECTIONS = {"forward": (1, 0), "backward": (-1, 0), "left": (0, 1), "right": (0, -1)}
PUSH_S = 0.1


def recovers(direction: tuple[int, int], force: float) -> bool:
    """Whether the robot recovers a push of ``force`` [N] along ``direction`` (world x, y)."""
    push = {"link": "root_link", "force": [force * direction[0], force * direction[1], 0.0],
            "start_s": 1.0, "duration_s": PUSH_S}
    result = sm.run_scenario(SCENARIO, {"disturbances": [push], "simulation.duration_s": 3.0})
    return result.status == "completed"


def largest_recovered(direction: tuple[int, int], upper: float, tolerance: float) -> float:
    """Bisects the largest recovered force in [0, upper] to ``tolerance`` [N]."""
    lower = 0.0
    if recovers(direction, upper):
        return upper
    while upper - lower > tolerance:
        middle = 0.5 * (lower + upper)
        lower, upper = (middle, upper) if recovers(direction, middle) else (lower, middle)
    return lower


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    tolerance = 20.0 if args.quick else 2.0
    forces = {name: largest_recovered(d, 600.0, tolerance) for name, d in DIRECTIONS.items()}
    print(f"{'direction':>10} {'force [N]':>10} {'impulse [N s]':>14}")
    for name, force in forces.items():
        print(f"{name:>10} {force:10.1f} {force * PUSH_S:14.2f}")
    figure, axis = plt.subplots(figsize=(6, 4))
    axis.bar(list(forces), np.array(list(forces.values())) * PUSH_S)
    axis.set_ylabel(f"largest recovered impulse [N s] (+- {tolerance * PUSH_S:.1f})")
    axis.set_title("iCub on two feet, 0.1 s push on the pelvis")
    save(figure, args.out / "push_table.png")


if __name__ == "__main__":
    main()
