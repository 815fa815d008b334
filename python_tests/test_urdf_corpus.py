"""The URDF corpus of two PyPI packages, ``icub-models`` and ``example-robot-data`` (real robots:
iCub versions, Talos, Romeo, G1, ANYmal, Tiago, Baxter, PR2, arms, hands), against Pinocchio.

Every file that Pinocchio loads with a free-flyer base (``pin.buildModelFromUrdf(path,
pin.JointModelFreeFlyer())``) loads here too, with the same moving joints, and M(q), h(q, nu)
and g(q) agree to 1e-10 relative at a few random states (joints matched by name, Pinocchio's
conventions converted by ``pin_reference.PinReference``). Physically doubtful inertias load with
one Python warning each, also listed in ``Model.warnings``; ``strict=True`` refuses them.

The counts (files, loaded by Pinocchio, loaded here) are printed by the summary test
(``pytest -s``) and its assertion message.
"""

from __future__ import annotations

import importlib.metadata
import pathlib
import warnings

import numpy as np
import pinocchio as pin
import pytest
import sea_momentum
from pin_reference import PinReference, random_state

PACKAGES = ("icub-models", "example-robot-data")
N_STATES = 3
RELATIVE_TOLERANCE = 1e-10


def corpus() -> list[pathlib.Path]:
    """Every ``.urdf`` file shipped by the packages (missing package: the test fails)."""
    files = []
    for package in PACKAGES:
        for f in importlib.metadata.files(package) or []:
            if str(f).endswith(".urdf"):
                files.append(pathlib.Path(str(f.locate())).resolve())
    return sorted(files)


CORPUS = corpus()


def short_name(path: pathlib.Path) -> str:
    """`robot_dir/file.urdf`, unique in the corpus (iCub files are all `model.urdf`)."""
    return f"{path.parent.name}/{path.name}" if path.name == "model.urdf" else path.name


def pinocchio_loads(path: pathlib.Path) -> bool:
    try:
        pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    except Exception:  # noqa: BLE001  (urdfdom and Pinocchio raise several types)
        return False
    return True


def load_ours(path: pathlib.Path) -> tuple[sea_momentum.Model, list[str]]:
    """Our model and the messages of the warnings it emitted."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = sea_momentum.Model.from_urdf(path)
    return model, [str(w.message) for w in caught if issubclass(w.category, UserWarning)]


def assert_close(ours: np.ndarray, reference: np.ndarray, what: str) -> None:
    scale = max(1.0, float(np.abs(reference).max()))
    error = float(np.abs(ours - reference).max())
    assert error <= RELATIVE_TOLERANCE * scale, f"{what}: max error {error:.3e}, scale {scale:.3e}"


def test_the_corpus_is_there():
    # icub-models 3.2 ships 16 files, example-robot-data 6.0 ships 69.
    assert len(CORPUS) >= 80, [str(p) for p in CORPUS]


@pytest.mark.parametrize("path", CORPUS, ids=short_name)
def test_loads_where_pinocchio_loads_and_agrees(path):
    if not pinocchio_loads(path):
        # Pinocchio refuses it (ur3.urdf: an empty <robot>): ours may refuse too, with a
        # ModelError naming the problem.
        try:
            load_ours(path)
        except sea_momentum.ModelError:
            pass
        return
    model, emitted = load_ours(path)
    assert emitted == [f"{path}: {w}" for w in model.warnings]
    reference = PinReference(path, joints=model.joint_names)
    assert sorted(reference.full_model.names[2:]) == sorted(model.joint_names)
    rng = np.random.default_rng(sum(path.name.encode()))
    for k in range(N_STATES):
        q, nu, _ = random_state(rng, model.n_joints)
        where = f"{short_name(path)}, state {k}"
        assert_close(model.mass_matrix(q), reference.mass_matrix(q), f"M, {where}")
        assert_close(model.bias_forces(q, nu), reference.bias_forces(q, nu), f"h, {where}")
        assert_close(model.gravity_forces(q), reference.gravity_forces(q), f"g, {where}")


def test_counts_ours_and_pinocchios():
    pin_loaded = {p for p in CORPUS if pinocchio_loads(p)}
    ours_loaded = set()
    for p in CORPUS:
        try:
            load_ours(p)
        except sea_momentum.ModelError:
            continue
        ours_loaded.add(p)
    summary = (
        f"{len(CORPUS)} files: Pinocchio loads {len(pin_loaded)}, sea_momentum loads "
        f"{len(ours_loaded)}; only Pinocchio: {sorted(short_name(p) for p in pin_loaded - ours_loaded)}; "
        f"only sea_momentum: {sorted(short_name(p) for p in ours_loaded - pin_loaded)}"
    )
    print(summary)
    assert pin_loaded <= ours_loaded, summary


def test_doubtful_inertias_warn_and_strict_refuses():
    talos = next(p for p in CORPUS if p.name == "talos_reduced.urdf")
    model, emitted = load_ours(talos)
    # A 0.01 kg camera frame without rotational inertia.
    assert any("rgbd_optical_frame" in w and "point mass" in w for w in model.warnings)
    assert len(emitted) == len(model.warnings)
    with pytest.raises(sea_momentum.ModelError, match="rgbd_optical_frame|point mass"):
        sea_momentum.Model.from_urdf(talos, strict=True)
    # Romeo's hand and finger joints move massless links only (M(q) is singular there): one
    # warning per topmost such joint, four chains per hand.
    romeo = next(p for p in CORPUS if p.name == "romeo.urdf")
    model, _ = load_ours(romeo)
    massless = [w.split("'")[1] for w in model.warnings if "moves no mass" in w]
    assert sorted(massless) == sorted(
        f"{side}{chain}" for side in "LR" for chain in ("Hand", "Finger21", "Finger31", "Thumb1")
    ), model.warnings
    # Panda's second finger mimics the first: both move on their own, the coupling named.
    panda = next(p for p in CORPUS if p.name == "panda.urdf")
    model, _ = load_ours(panda)
    assert [w for w in model.warnings if "mimics" in w] == [
        "joint 'panda_finger_joint2': mimics joint 'panda_finger_joint1' (multiplier 1, offset 0): "
        "the coupling is not modelled, the joint moves on its own"
    ]
    assert {"panda_finger_joint1", "panda_finger_joint2"} <= set(model.joint_names)
    # A clean description loads without a warning, also strictly.
    genova04 = next(p for p in CORPUS if p.parent.name == "iCubGenova04")
    assert sea_momentum.Model.from_urdf(genova04, strict=True).warnings == []
