"""Scenes: loading, dicts, dotted keys, and errors with the program's messages."""

import contextlib
import io
import os
import sys

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
    # as the scene gives it, to the last digit (was 1.9999999999999185e-5)
    assert joint["clearance_m"] == 2e-5
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
        f"{STANDARD}: invalid value for `clearance.3.clearance_mm`: `3` is no element there "
        "(expected an array index in [0, 1))"
    )
    with pytest.raises(jointwear.SceneError, match="expected a TOML value"):
        scene.set("run.rotations", None)


def test_a_misspelt_key_or_wrong_type_is_refused_at_set_and_changes_nothing():
    scene = jointwear.Scene.load(STANDARD)
    before = scene.to_dict()
    misspelt = {
        "run.rotatons": ("rotatons", 3),
        "driver.sped_rpm": ("sped_rpm", -1000.0),
        "clearance.0.clearence_mm": ("clearence_mm", 0.1),
    }
    for key, (field, value) in misspelt.items():
        with pytest.raises(jointwear.SceneError, match=f"unknown field `{field}`") as e:
            scene.set(key, value)
        # the message says which call it came from
        assert f'set("{key}"' in str(e.value)
        assert scene.to_dict() == before, key
    with pytest.raises(jointwear.SceneError, match="rotations"):
        scene.set("run.rotations", "ten")
    assert scene.to_dict() == before
    # the scene is not left broken: a correct set after the refused ones works
    assert scene.set("driver.speed_rpm", -1000.0).check()["period_s"] == pytest.approx(
        0.06, rel=1e-12
    )


def _notes(stderr, prefix):
    """The (key, value) pairs of the notes `note: <prefix> sets KEY = VALUE` in `stderr`."""
    lead = f"note: {prefix} sets "
    return sorted(
        tuple(line[len(lead) :].split(" = ", 1)) for line in stderr.splitlines() if line.startswith(lead)
    )


def test_set_rotations_cuts_snapshots_and_recording_as_the_programs_rotations(
    tmp_path, cli, capfd
):
    capfd.readouterr()
    scene = jointwear.Scene.load(STANDARD).set("run.rotations", 1)
    python = _notes(capfd.readouterr().err, 'set("run.rotations", 1)')
    run = scene.to_dict()["run"]
    # the file records 2 rotations and snapshots at 10..40; both are cut to one rotation
    assert (run["record_rotations"], run["wear_snapshots"]) == (1, [])
    assert scene.check()["rotations"] == 1
    program = cli("run", STANDARD, "--rotations", "1", "--out", tmp_path / "out")
    assert program.returncode == 0, program.stderr
    cuts = _notes(program.stderr, "--rotations 1")
    assert python == cuts == [("run.record_rotations", "1"), ("run.wear_snapshots", "[]")]
    # a value set on this scene is the user's, as with --set: kept, then refused as too long
    scene = jointwear.Scene.load(STANDARD).set("run.record_rotations", 2)
    scene.set("run.rotations", 1)
    assert scene.to_dict()["run"]["record_rotations"] == 2
    with pytest.raises(jointwear.SceneError, match="record_rotations"):
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


@pytest.mark.parametrize(
    "k_over_h, cause",
    [
        # wears past a tenth of the bearing radius in the first rotation
        (1e-6, "beyond the wear model's limit"),
        # wears the bearing ten times as steep as the paper's gap holds to in its first
        # rotation, which stops at its end
        (3e-9, "above the 0.3 up to which the paper's gap"),
    ],
)
def test_a_failure_while_running_is_a_simulation_error_with_the_programs_message(
    tmp_path, cli, k_over_h, cause
):
    path = short_file(tmp_path, **{"clearance.0.wear.k_over_h_per_pa": k_over_h})
    program = cli("run", path, "--out", tmp_path / "out")
    assert program.returncode == 1, program.stderr
    with pytest.raises(jointwear.SimulationError) as e:
        jointwear.Scene.load(path).run()
    assert isinstance(e.value, RuntimeError)
    assert cause in str(e.value)
    assert program.stderr == f"error: {e.value}\n"


def test_ensemble_and_sweep_arguments_are_checked_at_the_call():
    scene = short(jointwear.Scene.load(STANDARD))
    # 2.5 members used to run 2 members, -1 to raise OverflowError
    for bad in (2.5, "3", True):
        with pytest.raises(TypeError, match="members"):
            scene.ensemble(members=bad)
        with pytest.raises(TypeError, match="members"):
            scene.sweep({"driver.speed_rpm": [-2000.0]}, members=bad)
    # 0 is refused by the native call with the program's range (test_ensemble_sweep.py)
    with pytest.raises(jointwear.SceneError, match=r"`members`: -1 \(expected a positive integer\)"):
        scene.ensemble(members=-1)
    with pytest.raises(jointwear.SceneError, match="`seed`: -1"):
        scene.ensemble(members=2, seed=-1)
    # a bare value (or a string, which would sweep its characters, or a dict, its keys) is
    # not a list of values
    for bad in (1000, "1000", {-600: 1}):
        with pytest.raises(TypeError, match="sweep values must be a sequence") as e:
            scene.sweep({"driver.speed_rpm": bad})
        assert "'driver.speed_rpm'" in str(e.value)
    # numpy integers are integers
    assert scene.ensemble(members=np.int64(2)).members == 2
    # a grid or a scene that is not a dict, and a key that is not a string, are named (they
    # raised "list indices must be integers", "dictionary update sequence element" and
    # "'int' object is not an instance of 'str'")
    with pytest.raises(TypeError, match="grid must be a dict"):
        scene.sweep([("driver.speed_rpm", [-600])])
    with pytest.raises(TypeError, match="grid keys must be dotted keys"):
        scene.sweep({0: [-600]})
    with pytest.raises(TypeError, match="data must be a dict"):
        jointwear.Scene.from_dict([("title", "x")])
    with pytest.raises(TypeError, match="key must be a dotted key"):
        scene.set(0, 1)
    with pytest.raises(TypeError, match="base_dir must be a path"):
        jointwear.Scene.from_dict({"extends": "standard.toml"}, base_dir=5)


# Fails without os.fsdecode: a bytes path raised "'bytes' object is not an instance of 'str'".
def test_bytes_paths_are_paths(tmp_path):
    scene = short(jointwear.Scene.load(os.fsencode(STANDARD)))
    assert scene.path == str(STANDARD)
    scene.run().save(os.fsencode(tmp_path / "run"))
    assert (tmp_path / "run" / "summary.json").exists()


# Fails without the notes on sys.stderr: they went to the process's stderr, which a notebook
# does not show, so the snapshots cut by set("run.rotations", n) and a reversed driver
# passed unseen there (this redirect stands for the notebook's stream).
def test_notes_go_to_pythons_stderr():
    scene = jointwear.Scene.load(STANDARD)
    with contextlib.redirect_stderr(io.StringIO()) as err:
        scene.set("run.rotations", 2)
        scene.set("driver.speed_rpm", 600)
    text = err.getvalue()
    assert 'note: set("run.rotations", 2) sets run.wear_snapshots = []' in text
    assert "note: driver.speed_rpm = 600 reverses the driver" in text
    short(scene).set("driver.speed_rpm", -2000)
    with contextlib.redirect_stderr(io.StringIO()) as err:
        scene.sweep({"driver.speed_rpm": [500]})
    assert err.getvalue().count("reverses the driver") == 1


# Fails without a note that cannot fail: with sys.stderr None (pythonw) set() raised
# AttributeError after making its change, and the sweep raised before any case ran.
def test_a_note_without_a_stream_does_not_fail_the_call(monkeypatch):
    scene = jointwear.Scene.load(STANDARD)
    monkeypatch.setattr(sys, "stderr", None)
    scene.set("run.rotations", 2)
    assert scene.to_dict()["run"]["rotations"] == 2
    assert len(short(scene).sweep({"driver.speed_rpm": [500]})) == 1

    class Broken(io.StringIO):
        def write(self, text):
            raise OSError("the stream is gone")

    # a stream that fails to write: the error is reported as unraisable, the call succeeds
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    monkeypatch.setattr(sys, "stderr", Broken())
    scene.set("driver.speed_rpm", 700)
    assert scene.to_dict()["driver"]["speed_rpm"] == 700
    assert [str(u.exc_value) for u in unraisable] == ["the stream is gone"]


def test_a_set_that_reverses_the_driver_is_noted(capfd):
    scene = short(jointwear.Scene.load(STANDARD))
    capfd.readouterr()
    scene.set("driver.speed_rpm", -600)
    assert "reverses" not in capfd.readouterr().err
    scene.set("driver.speed_rpm", 600)
    # against the scene as loaded (checked to fail when compared with the scene before this set)
    assert capfd.readouterr().err.startswith(
        "note: driver.speed_rpm = 600 reverses the driver: the scene turns it at -2000 r/min"
    )
    scene.set("driver.speed_rpm", -2000)
    assert "reverses" not in capfd.readouterr().err
    # a sweep notes each reversing value once, before it runs
    scene.sweep({"driver.speed_rpm": [-600, 500]})
    err = capfd.readouterr().err
    assert err.count("reverses the driver") == 1
    assert "driver.speed_rpm = 500 reverses" in err
