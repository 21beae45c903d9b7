"""Scenes: loading, dicts, dotted keys, and errors with the program's messages."""

import numpy as np
import pytest

import jointwear
from conftest import SCENES, STANDARD, short, short_file


def test_load_checks_and_describes_the_scene():
    scene = jointwear.Scene.load(STANDARD)
    info = scene.check()
    assert info["title"] == "Standard slider-crank, c = 0.02 mm, 2000 r/min"
    assert info["bodies"] == ["crank", "rod", "slider"]
    (joint,) = info["joints"]
    assert joint["name"] == "rod-slider"
    assert joint["sectors"] == 360
    # 0.02 mm in the file, SI here
    assert joint["clearance_m"] == pytest.approx(2e-5, rel=1e-12)
    # a driven single-loop linkage has 0 degrees of freedom plus 2 per clearance joint
    assert info["dof"] == 2
    # 2000 r/min
    assert info["period_s"] == pytest.approx(0.03, rel=1e-12)
    assert scene.path == str(STANDARD)


def test_a_dict_scene_is_the_file_scene():
    from_file = short(jointwear.Scene.load(STANDARD))
    from_dict = jointwear.Scene.from_dict(from_file.to_dict())
    assert from_dict.path == "<dict>"
    assert from_dict.to_dict() == from_file.to_dict()
    a, b = from_file.run(), from_dict.run()
    assert np.array_equal(a.wear["rod-slider"], b.wear["rod-slider"])


def test_a_dict_scene_extends_a_file_beside_base_dir():
    scene = jointwear.Scene.from_dict(
        {
            "extends": "standard.toml",
            "title": "wider",
            "overrides": {"clearance.0.clearance_mm": 0.2},
        },
        base_dir=SCENES,
    )
    d = scene.to_dict()
    assert d["title"] == "wider"
    assert d["clearance"][0]["clearance_mm"] == 0.2
    assert d["driver"]["speed_rpm"] == -2000.0
    assert scene.check()["joints"][0]["clearance_m"] == pytest.approx(2e-4, rel=1e-12)


def test_set_takes_dotted_keys_and_python_values():
    scene = jointwear.Scene.load(STANDARD)
    other = scene.copy()
    assert scene.set("clearance.0.clearance_mm", np.float64(0.1)) is scene
    scene.set("driver.speed_rpm", 600).set("run.method", "dop853")
    scene.set("run.wear_snapshots", (np.int64(10), 40))
    d = scene.to_dict()
    assert d["clearance"][0]["clearance_mm"] == 0.1
    assert d["driver"]["speed_rpm"] == 600
    assert d["run"]["method"] == "dop853"
    assert d["run"]["wear_snapshots"] == [10, 40]
    assert scene.check()["period_s"] == pytest.approx(0.1, rel=1e-12)
    # the copy is independent
    assert other.to_dict()["clearance"][0]["clearance_mm"] == 0.02


def test_a_key_that_does_not_exist_is_a_scene_error():
    scene = jointwear.Scene.load(STANDARD)
    with pytest.raises(jointwear.SceneError) as e:
        scene.set("clearance.3.clearance_mm", 0.1)
    assert str(e.value) == (
        f"{STANDARD}: invalid value for `clearance.3.clearance_mm`: (at `3`) "
        "(expected an array index in [0, 1))"
    )
    with pytest.raises(jointwear.SceneError, match="expected a TOML value"):
        scene.set("run.rotations", None)
    # an unknown key is refused when the scene is next checked
    scene.set("run.rotatoins", 3)
    with pytest.raises(jointwear.SceneError, match="unknown field `rotatoins`"):
        scene.check()


def test_scene_errors_are_value_errors_with_the_programs_message(tmp_path, cli):
    cases = {
        "range.toml": short_file(tmp_path, "range.toml", **{"clearance.0.clearance_mm": -1.0}),
        "mass.toml": short_file(tmp_path, "mass.toml", **{"bodies.1.mass_kg": 1e-300}),
        "snapshot.toml": short_file(tmp_path, "snapshot.toml", **{"run.wear_snapshots": [5]}),
    }
    syntax = tmp_path / "syntax.toml"
    syntax.write_text("title = \n")
    cases["syntax.toml"] = syntax
    cases["missing.toml"] = tmp_path / "missing.toml"
    for name, path in cases.items():
        program = cli("check", path)
        assert program.returncode == 2, (name, program.stderr)
        with pytest.raises(jointwear.SceneError) as e:
            jointwear.Scene.load(path)
        assert isinstance(e.value, ValueError)
        assert program.stderr == f"error: {e.value}\n", name


def test_a_bad_value_set_from_python_has_the_message_of_the_same_value_in_a_file(tmp_path, cli):
    path = short_file(tmp_path, "bad.toml", **{"clearance.0.contact.restitution": 1.5})
    program = cli("check", path)
    scene = short(jointwear.Scene.load(STANDARD)).set("clearance.0.contact.restitution", 1.5)
    with pytest.raises(jointwear.SceneError) as e:
        scene.run()
    # the same message, naming the scene each came from
    assert program.stderr.strip() == f"error: {str(e.value).replace(str(STANDARD), str(path))}"
    with pytest.raises(jointwear.SceneError) as d:
        jointwear.Scene.from_dict(scene.to_dict())
    assert str(d.value) == str(e.value).replace(str(STANDARD), "<dict>")


def test_a_failure_while_running_is_a_simulation_error_with_the_programs_message(tmp_path, cli):
    # k/H = 1e-6 1/Pa wears past a tenth of the bearing radius in the first rotation
    path = short_file(tmp_path, **{"clearance.0.wear.k_over_h_per_pa": 1e-6})
    program = cli("run", path, "--out", tmp_path / "out")
    assert program.returncode == 1, program.stderr
    with pytest.raises(jointwear.SimulationError) as e:
        jointwear.Scene.load(path).run()
    assert isinstance(e.value, RuntimeError)
    assert program.stderr == f"error: {e.value}\n"
