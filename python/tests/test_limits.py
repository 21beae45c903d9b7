"""Inputs that used to crash the interpreter: a scene dict that contains itself, or nesting far
deeper than any scene, is a SceneError. Each case runs in a child interpreter, so that the
crash it used to be (a segmentation fault from a stack overflow) fails the test instead of
killing the test run."""

import subprocess
import sys

import pytest

CASES = {
    # from_dict copies the outer dict: the cycle closes one level down
    "a dict that contains itself": (
        "d = jointwear.Scene.load(STANDARD).to_dict(); d['ground'] = d",
        "jointwear.Scene.from_dict(d)",
        "invalid value for `ground.ground`: a dict that contains itself",
    ),
    "a list that contains itself": (
        "v = [1.0]; v.append(v)",
        "jointwear.Scene.load(STANDARD).set('gravity_m_s2', v)",
        "invalid value for `gravity_m_s2.1`: a list that contains itself",
    ),
    # 100 000 levels: bounded by the 64 read before the refusal
    "a list nested 100 000 deep": (
        "x = 0.0\nfor _ in range(100_000): x = [x]",
        "jointwear.Scene.from_dict({'title': x})",
        "invalid value for `title.0.0.0.0.0.0.0…`: nested deeper than 64 dicts and lists",
    ),
    "a dict nested 100 000 deep": (
        "x = {}\nfor _ in range(100_000): x = {'a': x}",
        "jointwear.Scene.from_dict({'run': x})",
        "invalid value for `run.a.a.a.a.a.a.a…`: nested deeper than 64",
    ),
}


@pytest.mark.parametrize("name", CASES)
def test_self_reference_and_deep_nesting_are_scene_errors(name):
    setup, call, message = CASES[name]
    from conftest import STANDARD

    program = f"""
import jointwear
STANDARD = {str(STANDARD)!r}
{setup}
try:
    {call}
except jointwear.SceneError as e:
    print(e)
else:
    print("accepted")
"""
    child = subprocess.run(
        [sys.executable, "-c", program], capture_output=True, text=True
    )
    assert child.returncode == 0, f"the interpreter died ({child.returncode}): {child.stderr}"
    assert message in child.stdout, child.stdout


def test_nesting_within_the_limit_reaches_validation():
    import jointwear

    # 60 levels: converted, then refused as a value of the wrong type, not for its depth
    x = 0.0
    for _ in range(60):
        x = [x]
    with pytest.raises(jointwear.SceneError, match="title") as e:
        jointwear.Scene.from_dict({"title": x})
    assert "nested deeper" not in str(e.value)


def test_check_names_where_a_fourbar_cannot_close():
    import jointwear
    from conftest import SCENES

    # ground 120, crank 40, coupler 30, rocker 90 mm: past about 80 deg of crank angle the
    # coupler and rocker cannot reach (the crank pin is more than 120 mm from the rocker pivot)
    scene = jointwear.Scene.load(SCENES / "fourbar.toml")
    scene.set("ground.points_mm.D", [120.0, 0.0])
    scene.set("bodies.0.points_mm", {"O": [-20.0, 0.0], "A": [20.0, 0.0]})
    scene.set("bodies.0.position_mm", [20.0, 0.0])
    scene.set("bodies.1.points_mm", {"A": [-15.0, 0.0], "B": [15.0, 0.0]})
    scene.set("bodies.2.points_mm", {"D": [-45.0, 0.0], "B": [45.0, 0.0]})
    # assembled at crank angle 0 with the pin B at (35, 29.58) mm
    scene.set("bodies.1.position_mm", [37.5, 14.79]).set("bodies.1.angle_deg", 99.6)
    scene.set("bodies.2.position_mm", [77.5, 14.79]).set("bodies.2.angle_deg", 160.8)
    with pytest.raises(jointwear.SceneError, match="cannot turn from 80.4 to 279.6 deg"):
        scene.check()
