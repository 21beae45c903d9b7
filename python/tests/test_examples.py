"""The example scripts run, in their quick settings, and write their figures (skipped without
matplotlib; scripts/test.sh installs it)."""

import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("matplotlib")


def run_example(name, *args):
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / name), *map(str, args)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_fig06_draws_the_mean_wear_after_10_to_40_rotations(tmp_path):
    out = tmp_path / "fig06.png"
    stdout = run_example("fig06.py", "--members", 2, "--out", out)
    assert out.stat().st_size > 10_000
    # the deepest mean wear grows with every snapshot
    depths = [float(line.split("wear ")[1].split()[0]) for line in stdout.splitlines() if "deepest" in line]
    assert len(depths) == 4 and depths == sorted(depths) and depths[0] > 0


def test_the_design_study_finds_a_grid_point_and_draws_the_grid(tmp_path):
    out = tmp_path / "study.png"
    stdout = run_example("design_study.py", "--quick", "--out", out)
    assert out.stat().st_size > 10_000
    assert "best grid point: clearance" in stdout and "answer: clearance" in stdout
