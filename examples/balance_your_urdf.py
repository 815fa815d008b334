"""Your URDF balanced: ``init_scenario`` writes a two-feet scenario for a robot, then it runs.

The robot here is ``urdf/mini_biped.urdf`` (8.5 kg, legs of 5 joints); pass ``--urdf`` and
``--contacts`` for yours (``--foot`` when its soles have no collision geometry to measure).
Prints what ``init`` found and the run's summary; draws the CoM against its reference.

Run: ``python examples/balance_your_urdf.py [--urdf U --contacts L R --foot X0,X1,Y0,Y1]``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import ROOT, arguments, save  # noqa: E402


def robot_arguments(parser) -> None:
    """The robot's URDF, its two contact frames and the foot rectangle."""
    parser.add_argument("--urdf", default=str(ROOT / "urdf" / "mini_biped.urdf"))
    parser.add_argument("--contacts", nargs=2, default=["l_sole", "r_sole"])
    parser.add_argument("--foot", default="-0.05,0.08,-0.03,0.03",
                        help="X0,X1,Y0,Y1 in the contact frame [m]; 'measure' for the collision geometry")


def main() -> None:
    args = arguments(__doc__.splitlines()[0], robot_arguments)
    foot = None if args.foot == "measure" else tuple(float(v) for v in args.foot.split(","))
    scenario = args.out / "your_robot.toml"
    info = sm.init_scenario(args.urdf, tuple(args.contacts), scenario, foot=foot)
    print(f"init: {info['robot']}, {info['mass']:.2f} kg, {info['joints']} joints, "
          f"foot x {info['foot_x']}, y {info['foot_y']} -> {scenario}")
    duration = 1.0 if args.quick else 5.0
    result = sm.run_scenario(scenario, {"simulation.duration_s": duration})
    summary = result.summary
    print(f"run: {result.status}, CoM error rms {summary.com_error_rms_m * 1e6:.1f} um, "
          f"final joint error {summary.joint_error_norm_final_rad:.4f} rad")
    figure, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 6))
    for axis, name, index in zip(axes, "xyz", range(3)):
        axis.plot(result.time, result.com[:, index], label="CoM")
        axis.plot(result.time, result.com_reference[:, index], "--", label="reference")
        axis.set_ylabel(f"CoM {name} [m]")
    axes[0].legend()
    axes[0].set_title(f"{info['robot']} balanced ({result.status})")
    axes[-1].set_xlabel("time [s]")
    save(figure, args.out / "balance_your_urdf.png")
    if result.status != "completed":
        raise SystemExit(f"the run did not complete: {summary.reason}")


if __name__ == "__main__":
    main()
