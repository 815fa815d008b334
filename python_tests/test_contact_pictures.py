"""The feet's contact points in Python under unilateral contacts: the run's result has each
point's position, force and activity (and the ground's normal), and
:func:`sea_momentum.contact_pictures.contact_points_figure` draws one force line per point,
the lifted spans, and the points and centres of pressure in a top view."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import sea_momentum as sm
from sea_momentum import contact_pictures
from sea_momentum._native import scenario_urdf

matplotlib.use("Agg")

PUSH = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: The iCub of the push scenario on the ground, dropped from 2 mm: both feet are in the air
#: for the first samples (about 20 ms), then touch down and carry the robot.
DROPPED = {
    "plant.contact_model": "unilateral",
    "controller.stiffness_identification": False,
    "ground.height_m": -0.002,
    "disturbances": [],
    "simulation.stop_at_joint_limits": False,
    "simulation.duration_s": 0.2,
    "simulation.record_every": 1,
}


@pytest.fixture(scope="module")
def dropped() -> sm.ScenarioResult:
    return sm.run_scenario(PUSH, DROPPED)


def test_the_result_has_each_contact_points_position_force_and_activity(dropped):
    result = dropped
    assert result.status == "completed", result.summary.reason
    m = len(result.time)
    assert result.contacts == ["l_sole", "r_sole"]
    assert result.contact_points == [4, 4]  # the soles' corners
    assert result.contact_point_positions.shape == (m, 8, 3)
    assert result.contact_point_forces.shape == (m, 8, 3)
    assert result.contact_point_active.shape == (m, 8) and result.contact_point_active.dtype == np.bool_
    assert result.ground_normal is not None
    np.testing.assert_allclose(result.ground_normal, [0.0, 0.0, 1.0], atol=1e-12)
    # In the air at first: no point touches, no force; at the end every point carries the
    # robot. The points' forces (at each sample's state) add up to each foot's contact wrench
    # (delivered over the sample's first plant step) within 1 % of the weight, but at the
    # touchdown's sample: there the step delivered the impact, which the state before it
    # does not hold.
    assert not result.contact_point_active[0].any()
    assert (result.contact_point_forces[0] == 0.0).all()
    assert result.contact_point_active[-1].all()
    weight = 9.81 * sm.Model.from_urdf(scenario_urdf(PUSH)).total_mass
    touchdown = int(np.argmax(result.contact_point_active.any(axis=1)))
    for c, contact in enumerate(result.contacts):
        columns = result.contact_point_slice(contact)
        points = result.contact_point_forces[:, columns].sum(axis=1)
        after = slice(touchdown + 1, None)
        np.testing.assert_allclose(points[after], result.contact_wrenches[after, c, :3], atol=0.01 * weight)
        np.testing.assert_array_equal(points[:touchdown], 0.0)
    # Along the ground's normal the points push, and at the end they carry the weight.
    normal = result.contact_point_normal_forces()
    assert (normal >= 0.0).all()
    assert abs(normal[-1].sum() - weight) < 0.1 * weight


def test_a_bilateral_run_has_no_contact_points():
    result = sm.run_scenario(PUSH, {"plant.contact_model": "bilateral", "disturbances": [], "simulation.duration_s": 0.05})
    assert result.contact_points == [] and result.ground_normal is None
    assert result.contact_point_positions.shape == (len(result.time), 0, 3)
    assert result.contact_point_normal_forces().shape == (len(result.time), 0)
    with pytest.raises(ValueError, match="unilateral"):
        contact_pictures.contact_points_figure(result)


def test_the_figure_draws_a_line_per_point_the_lifted_spans_and_the_top_view(dropped, tmp_path):
    import matplotlib.pyplot as plt

    result = dropped
    lifted = contact_pictures.foot_lifted(result, "l_sole")
    assert lifted[0] and not lifted[-1]
    fig = contact_pictures.contact_points_figure(result, instant=0.1)
    try:
        force_axes, top = fig.axes[:2], fig.axes[2]
        assert len(fig.axes) == 3
        for ax, contact in zip(force_axes, result.contacts):
            columns = result.contact_point_slice(contact)
            # One line per point, its data the point's normal force over time.
            assert len(ax.lines) == result.contact_points[result.contacts.index(contact)]
            for k, line in enumerate(ax.lines):
                x, y = line.get_data()
                np.testing.assert_array_equal(x, result.time)
                np.testing.assert_array_equal(y, result.contact_point_normal_forces()[:, columns][:, k])
            # The foot is in the air at first: one shaded span from t = 0 to its touchdown.
            spans = [p for p in ax.patches if p.get_facecolor()[:3] == pytest.approx(contact_pictures.LIFTED_RGBA[:3])]
            assert len(spans) == 1
            x0 = spans[0].get_x()
            assert x0 == 0.0 and 0.0 < spans[0].get_width() < 0.05
        # Top view: per foot a path per point and the CoP path; the points at t = 0.1 s
        # (all touching) as filled markers and the CoP inside the points' rectangle.
        assert len(top.lines) == 8 + 2
        row = int(np.argmin(abs(result.time - 0.1)))
        touching = [c for c in top.collections if len(c.get_offsets()) == 4]
        assert len(touching) == 2
        for c, contact in enumerate(result.contacts):
            columns = result.contact_point_slice(contact)
            np.testing.assert_allclose(
                np.asarray(touching[c].get_offsets()), result.contact_point_positions[row, columns, :2]
            )
            cop = contact_pictures.center_of_pressure(result, contact)[row]
            corners = result.contact_point_positions[row, columns]
            assert corners[:, 0].min() <= cop[0] <= corners[:, 0].max()
            assert corners[:, 1].min() <= cop[1] <= corners[:, 1].max()
        assert "t = 0.10 s" in top.get_title()
    finally:
        plt.close(fig)
    path = contact_pictures.contact_points_picture(result, tmp_path / "contacts.png")
    assert path.stat().st_size > 10_000
