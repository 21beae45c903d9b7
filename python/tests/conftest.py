"""Shared fixtures: the repository's scenes, a short standard scene, and the `jointwear`
program the bindings are compared with."""

import atexit
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

import jointwear

ROOT = Path(__file__).resolve().parents[2]

# The paper's outputs (figures/, data/, paper.md and their lock) of this session and of the
# programs it starts: a temporary root, never the checkout's, where a test's lock or save
# collided with a paper program or another test run. Set before any save or claim reads it.
PAPER_OUTPUTS = Path(tempfile.mkdtemp(prefix="jointwear-pytest-outputs-"))
atexit.register(shutil.rmtree, PAPER_OUTPUTS, ignore_errors=True)
os.environ["JOINTWEAR_OUTPUT_ROOT"] = str(PAPER_OUTPUTS)
SCENES = ROOT / "data" / "scenes"
STANDARD = SCENES / "standard.toml"

# Two rotations of the standard scene take about 20 ms: short enough for CI, long enough for
# contact, impacts and wear in the second rotation.
SHORT = {
    "run.rotations": 2,
    "run.record_rotations": 1,
    "run.wear_snapshots": [1, 2],
}


def short(scene):
    """`scene` shortened to the SHORT settings."""
    for key, value in SHORT.items():
        scene.set(key, value)
    return scene


def short_file(tmp_path: Path, name: str = "short.toml", **overrides) -> Path:
    """A scene file that extends the standard scene with the SHORT settings and `overrides`
    (dotted keys), as the program reads it."""
    lines = [f'extends = "{STANDARD.as_posix()}"', "[overrides]"]
    for key, value in {**SHORT, **overrides}.items():
        lines.append(f'"{key}" = {toml_value(value)}')
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return repr(value)


def find_cli():
    """The `jointwear` program: $JOINTWEAR_CLI, else the release build of the target
    directory, else None."""
    given = os.environ.get("JOINTWEAR_CLI")
    if given:
        return given
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for candidate in (target / "release" / "jointwear", ROOT / "target" / "release" / "jointwear"):
        if candidate.is_file():
            return str(candidate)
    return shutil.which("jointwear")


@pytest.fixture(scope="session")
def cli():
    """Runs the `jointwear` program; skips the test when it is not built (scripts/test.sh
    builds it and sets $JOINTWEAR_CLI, so there it never skips)."""
    program = find_cli()
    if program is None:
        pytest.skip("the jointwear program is not built (cargo build --release)")

    def run(*args, cwd=None):
        return subprocess.run(
            [program, *map(str, args)], capture_output=True, text=True, cwd=cwd
        )

    return run


@pytest.fixture(scope="session")
def short_run():
    """One short run of the standard scene, shared by the read-only tests."""
    return short(jointwear.Scene.load(STANDARD)).run()
