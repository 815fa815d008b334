"""sea_momentum against Pinocchio (through pin_reference, which converts Pinocchio's
conventions to ours and is validated on its own in test_pin_reference.py).

Models: iCubGenova04 with all 32 joints (default joint order, matched by name), reduced to the
paper's 25 joints (joints= list, locked joints at 0 and at non-zero values), the shipped
urdf/icub25.urdf, a hand-made URDF and random URDF trees from urdf_gen.py. Quantities: M, h,
gravity, RNEA, frame poses, frame Jacobians, Jdot_nu, CoM, CoM Jacobian, A_G, H; agreement to
1e-9 relative (norm-wise). Then the error API (ModelError for model problems, ValueError naming
the argument for bad arrays, an error naming an unknown frame).
"""

from __future__ import annotations

import math
import pathlib
import re

import numpy as np
import pytest

from pin_reference import (  # a helper beside the tests (see conftest.py)
    HAND_URDF,
    ICUB25_JOINTS,
    PinReference,
    random_state,
    urdf_depth_first_joints,
)

import sea_momentum as sm  # a failed import fails the run (no importorskip)

REPO = pathlib.Path(__file__).resolve().parent.parent
ICUB25_URDF = REPO / "urdf" / "icub25.urdf"
RTOL = 1e-9
ICUB_LOCKED = {"neck_pitch": 0.3, "l_wrist_pitch": -0.4, "r_wrist_yaw": 0.25, "neck_yaw": -0.2}
RANDOM_SEEDS = [0, 1, 2, 3, 4, 5, 6, 7]
RANDOM_REDUCED_SEEDS = [0, 1, 2]
STATE_SEEDS = [0, 1, 2]
# frames whose Jacobians and Jdot_nu are compared on the iCub (poses: every link)
ICUB_JAC_FRAMES = ["l_sole", "r_sole", "root_link", "l_hand", "r_hand", "head", "chest",
                   "l_foot", "r_lower_leg", "l_forearm"]


def close(ours, ref, what: str, rtol: float = RTOL) -> None:
    """||ours - ref|| <= rtol * max(1, ||ref||), with a readable failure."""
    ours = np.asarray(ours, dtype=float)
    ref = np.asarray(ref, dtype=float)
    assert ours.shape == ref.shape, f"{what}: shape {ours.shape}, expected {ref.shape}"
    err = np.linalg.norm(ours - ref)
    scale = max(1.0, float(np.linalg.norm(ref)))
    if not err <= rtol * scale:
        diff = np.abs(ours - ref)
        worst = np.unravel_index(np.argmax(diff), diff.shape)
        raise AssertionError(
            f"{what}: |ours - ref| = {err:.3e} > {rtol:.0e} * {scale:.3e}; worst entry {worst}: "
            f"ours {ours[worst]!r}, ref {ref[worst]!r}"
        )


# ------------------------------------------------------------------------- model cases


def _icub_path() -> pathlib.Path:
    import icub_models  # noqa: PLC0415  (a test dependency: missing means failed)

    return pathlib.Path(icub_models.get_model_file("iCubGenova04"))


def _urdf_gen():
    import urdf_gen  # noqa: PLC0415  (shipped beside the tests: missing means failed)

    return urdf_gen


class Case:
    """A pair (ours, ref) on the same URDF, joints and locked values."""

    def __init__(self, name, path, joints=None, locked=None, jac_frames=None):
        self.name = name
        self.path = pathlib.Path(path)
        kwargs = {}
        if joints is not None:
            kwargs["joints"] = list(joints)
        if locked is not None:
            kwargs["locked"] = dict(locked)
        self.ours = sm.Model.from_urdf(str(self.path), **kwargs)
        # joints=None: ours chooses the URDF order; the reference follows it by name.
        ref_joints = list(joints) if joints is not None else list(self.ours.joint_names)
        self.ref = PinReference(self.path, joints=ref_joints, locked=locked)
        self.joints = joints
        self.locked = locked
        self.all_frames = list(self.ref.frame_names)
        if jac_frames is None:
            self.jac_frames = self.all_frames
        else:
            self.jac_frames = [f for f in jac_frames if f in self.ref.frame_ids]


_CASES: dict[str, Case] = {}


def _make_case(name: str, tmp_dir: pathlib.Path) -> Case:
    if name == "icub32":
        return Case(name, _icub_path(), jac_frames=ICUB_JAC_FRAMES)
    if name == "icub25":
        return Case(name, _icub_path(), joints=ICUB25_JOINTS, jac_frames=ICUB_JAC_FRAMES)
    if name == "icub25_locked":
        return Case(name, _icub_path(), joints=ICUB25_JOINTS, locked=ICUB_LOCKED,
                    jac_frames=ICUB_JAC_FRAMES)
    if name == "icub25_file":
        return Case(name, ICUB25_URDF, jac_frames=ICUB_JAC_FRAMES)
    if name == "icub25_file_listed":
        return Case(name, ICUB25_URDF, joints=ICUB25_JOINTS, jac_frames=ICUB_JAC_FRAMES)
    if name == "hand":
        path = tmp_dir / "hand_made.urdf"
        path.write_text(HAND_URDF)
        return Case(name, path)
    if name == "hand_reduced":
        path = tmp_dir / "hand_made.urdf"
        path.write_text(HAND_URDF)
        return Case(name, path, joints=["gamma_rev", "zeta_rev", "beta_cont"],
                    locked={"alpha_pris": 0.12})
    if name.startswith("random_reduced-"):
        seed = int(name.split("-")[1])
        path = _urdf_gen().write_random_urdf(tmp_dir, seed, 12)
        movable = urdf_depth_first_joints(path.read_text())
        keep = list(reversed(movable[::2]))  # every other joint, reversed order
        rng = np.random.default_rng(seed)
        locked = {n: float(rng.uniform(-1, 1)) for n in movable if n not in keep}
        return Case(name, path, joints=keep, locked=locked)
    if name.startswith("random-"):
        seed = int(name.split("-")[1])
        path = _urdf_gen().write_random_urdf(tmp_dir, seed, 8 + seed % 5)
        return Case(name, path)
    raise KeyError(name)


CASE_NAMES = (
    ["icub32", "icub25", "icub25_locked", "icub25_file", "icub25_file_listed", "hand",
     "hand_reduced"]
    + [f"random-{s}" for s in RANDOM_SEEDS]
    + [f"random_reduced-{s}" for s in RANDOM_REDUCED_SEEDS]
)


@pytest.fixture(scope="module")
def tmp_dir(tmp_path_factory) -> pathlib.Path:
    return tmp_path_factory.mktemp("urdf_vs_pin")


@pytest.fixture(params=CASE_NAMES)
def case(request, tmp_dir) -> Case:
    name = request.param
    if name not in _CASES:
        _CASES[name] = _make_case(name, tmp_dir)
    return _CASES[name]


def _state(case: Case, seed: int):
    rng = np.random.default_rng(12345 + 7919 * seed)
    return random_state(rng, case.ref.n_joints, box=2.0, angle=math.pi, speed=2.0)


# ------------------------------------------------------------------------- structure


def test_structure(case):
    ours, ref = case.ours, case.ref
    assert ours.n_joints == ref.n_joints
    assert ours.nq == 7 + ref.n_joints
    assert ours.nv == 6 + ref.n_joints
    if case.joints is not None:
        assert list(ours.joint_names) == list(case.joints)
    else:
        assert sorted(ours.joint_names) == sorted(list(ref.full_model.names)[2:])
        # docs/reference/conventions.md: URDF tree order, depth first, children in file order
        assert list(ours.joint_names) == urdf_depth_first_joints(case.path.read_text())
    assert set(ours.frame_names) == set(ref.frame_names)
    assert ours.total_mass == pytest.approx(ref.total_mass, rel=1e-12)
    q0 = np.asarray(ours.neutral())
    np.testing.assert_array_equal(q0, ref.neutral())


# ------------------------------------------------------------------------- dynamics


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_mass_matrix(case, seed):
    q, _, _ = _state(case, seed)
    M = np.asarray(case.ours.mass_matrix(q))
    close(M, case.ref.mass_matrix(q), "M")
    np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-12 * max(1.0, np.abs(M).max()))


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_bias_forces(case, seed):
    q, nu, _ = _state(case, seed)
    close(case.ours.bias_forces(q, nu), case.ref.bias_forces(q, nu), "h")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_gravity_forces(case, seed):
    q, _, _ = _state(case, seed)
    close(case.ours.gravity_forces(q), case.ref.gravity_forces(q), "g")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_inverse_dynamics(case, seed):
    q, nu, nudot = _state(case, seed)
    close(case.ours.inverse_dynamics(q, nu, nudot), case.ref.inverse_dynamics(q, nu, nudot),
          "rnea")


# ------------------------------------------------------------------------- kinematics


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_frame_poses(case, seed):
    q, _, _ = _state(case, seed)
    for f in case.all_frames:
        H = np.asarray(case.ours.frame_pose(q, f))
        close(H, case.ref.frame_pose(q, f), f"pose {f}")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_frame_jacobians(case, seed):
    q, _, _ = _state(case, seed)
    for f in case.jac_frames:
        close(case.ours.frame_jacobian(q, f), case.ref.frame_jacobian(q, f), f"J {f}")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_frame_jacobian_dot_v(case, seed):
    q, nu, _ = _state(case, seed)
    for f in case.jac_frames:
        close(case.ours.frame_jacobian_dot_v(q, nu, f), case.ref.frame_jacobian_dot_v(q, nu, f),
              f"Jdot_nu {f}")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_com(case, seed):
    q, _, _ = _state(case, seed)
    close(case.ours.com(q), case.ref.com(q), "com")
    close(case.ours.com_jacobian(q), case.ref.com_jacobian(q), "com Jacobian")


@pytest.mark.parametrize("seed", STATE_SEEDS)
def test_centroidal(case, seed):
    q, nu, _ = _state(case, seed)
    close(case.ours.centroidal_momentum_matrix(q), case.ref.centroidal_momentum_matrix(q), "A_G")
    close(case.ours.centroidal_momentum(q, nu), case.ref.centroidal_momentum(q, nu), "H")


def test_sole_frames_on_icub(tmp_dir):
    """l_sole / r_sole are compared on every iCub case (guards the frame selection above)."""
    for name in ["icub32", "icub25", "icub25_locked"]:
        if name not in _CASES:
            _CASES[name] = _make_case(name, tmp_dir)
        c = _CASES[name]
        assert {"l_sole", "r_sole"} <= set(c.jac_frames)
        q, nu, _ = _state(c, 0)
        for f in ["l_sole", "r_sole"]:
            close(c.ours.frame_pose(q, f), c.ref.frame_pose(q, f), f"{name} pose {f}")
            close(c.ours.frame_jacobian(q, f), c.ref.frame_jacobian(q, f), f"{name} J {f}")


def test_neutral_pose_of_icub_feet(tmp_dir):
    """At q = neutral the base sits at the origin with identity orientation."""
    if "icub25" not in _CASES:
        _CASES["icub25"] = _make_case("icub25", tmp_dir)
    c = _CASES["icub25"]
    q0 = np.asarray(c.ours.neutral())
    for f in ["root_link", "l_sole", "r_sole"]:
        close(c.ours.frame_pose(q0, f), c.ref.frame_pose(q0, f), f"neutral pose {f}")
    np.testing.assert_allclose(np.asarray(c.ours.frame_pose(q0, "root_link")), np.eye(4),
                               atol=1e-15)


# ------------------------------------------------------------------------- model errors


def _link(name: str, mass: str = "1.0", inertia=("0.01", "0.01", "0.01", "0", "0", "0"),
          origin: str = "0 0 0") -> str:
    ixx, iyy, izz, ixy, ixz, iyz = inertia
    return (
        f'<link name="{name}"><inertial><origin xyz="{origin}" rpy="0 0 0"/>'
        f'<mass value="{mass}"/><inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}" iyy="{iyy}" '
        f'iyz="{iyz}" izz="{izz}"/></inertial></link>'
    )


def _joint(name: str, parent: str, child: str, jtype: str = "revolute",
           xyz: str = "0 0 0.1", axis: str | None = "0 0 1") -> str:
    axis_el = f'<axis xyz="{axis}"/>' if axis is not None and jtype != "fixed" else ""
    limit = ('<limit lower="-1" upper="1" effort="10" velocity="1"/>'
             if jtype in ("revolute", "prismatic") else "")
    return (
        f'<joint name="{name}" type="{jtype}"><origin xyz="{xyz}" rpy="0 0 0"/>'
        f'<parent link="{parent}"/><child link="{child}"/>{axis_el}{limit}</joint>'
    )


def _robot(*elements: str) -> str:
    return '<?xml version="1.0"?>\n<robot name="bad">\n' + "\n".join(elements) + "\n</robot>\n"


# a valid two-link robot, to check that the helpers produce loadable URDFs
GOOD = _robot(_link("base"), _joint("j1", "base", "link1"), _link("link1"))

BAD_URDFS = {
    "missing_child_link": (
        _robot(_link("base"), _joint("j_to_ghost", "base", "ghost_link")),
        ["ghost_link"],
    ),
    "kinematic_loop": (
        _robot(_link("base"), _link("loop_a"), _link("loop_b"),
               _joint("to_loop", "base", "loop_a"),
               _joint("loop_ab", "loop_a", "loop_b"),
               _joint("loop_ba", "loop_b", "loop_a")),
        ["loop_a", "loop_b", "loop_ab", "loop_ba"],
    ),
    "two_roots": (
        _robot(_link("base"), _link("link1"), _joint("j1", "base", "link1"),
               _link("other_root"), _link("other_child"),
               _joint("j_other", "other_root", "other_child")),
        ["base", "other_root"],
    ),
    "negative_mass": (
        _robot(_link("base"), _joint("j1", "base", "neg_mass_link"),
               _link("neg_mass_link", mass="-1.0")),
        ["neg_mass_link"],
    ),
    "inertia_not_pd": (
        _robot(_link("base"), _joint("j1", "base", "not_pd_link"),
               _link("not_pd_link", inertia=("-0.01", "0.01", "0.01", "0", "0", "0"))),
        ["not_pd_link"],
    ),
    "inertia_triangle": (
        _robot(_link("base"), _joint("j1", "base", "triangle_link"),
               _link("triangle_link", inertia=("1.0", "0.1", "0.1", "0", "0", "0"))),
        ["triangle_link"],
    ),
    "nan_origin": (
        _robot(_link("base"), _joint("nan_joint", "base", "link1", xyz="NaN 0 0.1"),
               _link("link1")),
        ["nan_joint"],
    ),
    "zero_axis": (
        _robot(_link("base"), _joint("zero_axis_joint", "base", "link1", axis="0 0 0"),
               _link("link1")),
        ["zero_axis_joint"],
    ),
    "floating_joint": (
        _robot(_link("base"), _joint("float_joint", "base", "link1", jtype="floating",
                                     axis=None),
               _link("link1")),
        ["float_joint"],
    ),
    "planar_joint": (
        _robot(_link("base"), _joint("planar_joint", "base", "link1", jtype="planar"),
               _link("link1")),
        ["planar_joint"],
    ),
    "duplicate_link": (
        _robot(_link("base"), _joint("j1", "base", "dup_link"), _link("dup_link"),
               _link("dup_link", mass="2.0")),
        ["dup_link"],
    ),
    "duplicate_joint": (
        _robot(_link("base"), _link("link1"), _link("link2"),
               _joint("dup_joint", "base", "link1"), _joint("dup_joint", "base", "link2")),
        ["dup_joint"],
    ),
}


def _write(tmp_path: pathlib.Path, name: str, text: str) -> pathlib.Path:
    path = tmp_path / f"{name}.urdf"
    path.write_text(text)
    return path


def _assert_names(exc: BaseException, names: list[str]) -> None:
    msg = str(exc)
    assert any(n in msg for n in names), f"message {msg!r} names none of {names}"


def test_model_error_is_value_error():
    assert issubclass(sm.ModelError, ValueError)


def test_good_helper_urdf_loads(tmp_path):
    model = sm.Model.from_urdf(str(_write(tmp_path, "good", GOOD)))
    assert model.n_joints == 1 and list(model.joint_names) == ["j1"]


# Physically doubtful, not unusable: they load with a warning naming the link (as Pinocchio
# loads them); only strict loading refuses them.
DOUBTFUL_URDFS = {"inertia_not_pd", "inertia_triangle"}


@pytest.mark.parametrize("name", sorted(BAD_URDFS))
def test_bad_urdf_raises_model_error(tmp_path, name):
    text, names = BAD_URDFS[name]
    path = _write(tmp_path, name, text)
    strict = name in DOUBTFUL_URDFS
    if strict:
        with pytest.warns(UserWarning) as record:
            sm.Model.from_urdf(str(path))
        _assert_names(record[0].message, names)
    with pytest.raises(sm.ModelError) as info:
        sm.Model.from_urdf(str(path), strict=strict)
    _assert_names(info.value, names)


def test_missing_file(tmp_path):
    path = tmp_path / "does_not_exist.urdf"
    with pytest.raises(OSError) as info:
        sm.Model.from_urdf(str(path))
    _assert_names(info.value, ["does_not_exist.urdf"])


def test_not_xml(tmp_path):
    path = _write(tmp_path, "not_xml", "this is not <xml at all\n{]")
    with pytest.raises(sm.ModelError):
        sm.Model.from_urdf(str(path))


def test_unknown_joint_in_list(tmp_path):
    path = _write(tmp_path, "good", GOOD)
    with pytest.raises(sm.ModelError) as info:
        sm.Model.from_urdf(str(path), joints=["no_such_joint"])
    _assert_names(info.value, ["no_such_joint"])


# ------------------------------------------------------------------------- argument errors


@pytest.fixture(scope="module")
def hand_model(tmp_dir):
    path = tmp_dir / "hand_made_args.urdf"
    path.write_text(HAND_URDF)
    return sm.Model.from_urdf(str(path))


def _valid(model):
    rng = np.random.default_rng(0)
    return random_state(rng, model.n_joints)


def _calls(model, q, nu, nudot):
    """Every array-taking method, called with (q, nu, nudot)."""
    return [
        lambda: model.mass_matrix(q),
        lambda: model.gravity_forces(q),
        lambda: model.bias_forces(q, nu),
        lambda: model.inverse_dynamics(q, nu, nudot),
        lambda: model.frame_pose(q, "sole"),
        lambda: model.frame_jacobian(q, "sole"),
        lambda: model.frame_jacobian_dot_v(q, nu, "sole"),
        lambda: model.com(q),
        lambda: model.com_jacobian(q),
        lambda: model.centroidal_momentum_matrix(q),
        lambda: model.centroidal_momentum(q, nu),
    ]


def _bad_variants(x: np.ndarray) -> dict[str, np.ndarray]:
    nan = x.copy()
    nan[-1] = np.nan
    inf = x.copy()
    inf[0] = np.inf
    return {
        "too_short": x[:-1].copy(),
        "too_long": np.r_[x, 0.0],
        "two_d": x.reshape(1, -1).copy(),
        "column": x.reshape(-1, 1).copy(),
        "nan": nan,
        "inf": inf,
    }


def _check_value_error(fn, arg: str) -> None:
    with pytest.raises(ValueError) as info:
        fn()
    msg = str(info.value)
    assert re.search(rf"\b{arg}\b", msg), f"message {msg!r} does not name {arg!r}"


@pytest.mark.parametrize("variant", ["too_short", "too_long", "two_d", "column", "nan", "inf"])
def test_bad_q(hand_model, variant):
    q, nu, nudot = _valid(hand_model)
    bad = _bad_variants(q)[variant]
    for fn in _calls(hand_model, bad, nu, nudot):
        _check_value_error(fn, "q")


@pytest.mark.parametrize("variant", ["too_short", "too_long", "two_d", "column", "nan", "inf"])
def test_bad_nu(hand_model, variant):
    q, nu, nudot = _valid(hand_model)
    bad = _bad_variants(nu)[variant]
    for fn in [
        lambda: hand_model.bias_forces(q, bad),
        lambda: hand_model.inverse_dynamics(q, bad, nudot),
        lambda: hand_model.frame_jacobian_dot_v(q, bad, "sole"),
        lambda: hand_model.centroidal_momentum(q, bad),
    ]:
        _check_value_error(fn, "nu")


@pytest.mark.parametrize("variant", ["too_short", "too_long", "two_d", "column", "nan", "inf"])
def test_bad_nudot(hand_model, variant):
    q, nu, nudot = _valid(hand_model)
    bad = _bad_variants(nudot)[variant]
    _check_value_error(lambda: hand_model.inverse_dynamics(q, nu, bad), "nudot")


def test_valid_calls_succeed(hand_model):
    """The argument tests above fail for the right reason: the same calls with valid arrays
    work."""
    q, nu, nudot = _valid(hand_model)
    for fn in _calls(hand_model, q, nu, nudot):
        fn()


def test_unknown_frame(hand_model):
    q, nu, _ = _valid(hand_model)
    for fn in [
        lambda: hand_model.frame_pose(q, "no_such_frame"),
        lambda: hand_model.frame_jacobian(q, "no_such_frame"),
        lambda: hand_model.frame_jacobian_dot_v(q, nu, "no_such_frame"),
    ]:
        with pytest.raises((ValueError, KeyError)) as info:
            fn()
        assert "no_such_frame" in str(info.value)
