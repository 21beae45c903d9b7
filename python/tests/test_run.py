"""Runs: against the `jointwear` program bit for bit, physical sanity, determinism, the GIL,
pandas."""

import csv
import json
import signal
import sys
import threading
import time
import warnings

import numpy as np
import pytest

import jointwear
from conftest import SCENES, STANDARD, short, short_file


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def test_a_run_is_the_programs_run_bit_for_bit(tmp_path, cli):
    path = short_file(tmp_path)
    out = tmp_path / "out"
    program = cli("run", path, "--out", out)
    assert program.returncode == 0, program.stderr
    run = jointwear.Scene.load(path).run()
    # The program writes every number with Rust's `{:e}`, the shortest text that reads back
    # to the same f64: equality here is equality of the bits.
    header, table = read_csv(out / "timeseries.csv")
    assert list(run.timeseries)[: len(header)] == header
    for i, name in enumerate(header):
        assert np.array_equal(run.timeseries[name], table[:, i]), name
    header, table = read_csv(out / "wear_rod-slider.csv")
    assert header == ["angle_deg", "depth_m"]
    assert np.array_equal(run.angles_deg["rod-slider"], table[:, 0])
    assert np.array_equal(run.wear["rod-slider"], table[:, 1])
    # and the summary the program prints (four significant digits, as `.4g` for a depth
    # below 1000 µm)
    depth_um = run.summary["rod-slider"]["max_wear_depth_m"] * 1e6
    assert f"depth {depth_um:.4g} µm" in program.stdout
    # the joint's contact onsets, named and counted as the program's summary.json does
    with open(out / "summary.json") as f:
        joint = json.load(f)["joints"][0]
    assert run.summary["rod-slider"]["contact_onsets"] == joint["contact_onsets"]


def test_a_run_is_physically_sane(short_run):
    run = short_run
    info = jointwear.Scene.load(STANDARD).check()["joints"][0]
    wear = run.wear["rod-slider"]
    angles = run.angles_deg["rod-slider"]
    assert wear.shape == angles.shape == (360,)
    assert np.allclose(angles, np.arange(360) + 0.5, rtol=0, atol=1e-12)
    assert (wear >= 0).all() and wear.max() > 0
    # snapshots after 1 and 2 rotations; wear only grows, and the last is the final profile
    assert run.snapshot_rotations.tolist() == [1, 2]
    snaps = run.snapshots["rod-slider"]
    assert snaps.shape == (2, 360)
    assert (snaps[1] >= snaps[0]).all() and snaps[1].sum() > snaps[0].sum()
    assert np.array_equal(snaps[1], wear)
    s = run.summary["rod-slider"]
    assert s["max_wear_depth_m"] == wear.max()
    # wear regions by prominence, the first at the deepest sector
    regions = s["wear_regions"]
    assert regions[0]["depth_m"] == wear.max()
    prominences = [r["prominence_m"] for r in regions]
    assert prominences == sorted(prominences, reverse=True)
    assert s["contact_onsets"] >= 1 and s["max_normal_force_recorded_n"] > 0
    # the recorded window's penetration is within the whole run's (which adds the start-up)
    assert 0 < s["max_penetration_recorded_m"] <= s["max_penetration_whole_run_m"]
    # one recorded rotation of 0.03 s every 1e-5 s
    t = run.timeseries["time_s"]
    assert len(t) == 3001 and np.allclose(np.diff(t), 1e-5, rtol=1e-6)
    assert t[0] == pytest.approx(0.03, rel=1e-9) and t[-1] == pytest.approx(0.06, rel=1e-9)
    for name, column in run.timeseries.items():
        assert column.shape == t.shape and np.isfinite(column).all(), name
    # the journal stays inside the worn clearance circle up to the recorded penetration
    e = np.hypot(run.timeseries["rod-slider.ex_m"], run.timeseries["rod-slider.ey_m"])
    bound = info["clearance_m"] + s["max_penetration_recorded_m"] + wear.max()
    assert e.max() <= bound + 1e-12
    assert (run.timeseries["rod-slider.normal_force_n"] >= 0).all()
    # penetration is e - c less the wear depth at the contact angle: wear only opens the gap,
    # by at most the deepest wear
    opened = e - info["clearance_m"] - run.timeseries["rod-slider.penetration_m"]
    assert opened.min() >= -1e-15 and opened.max() <= wear.max() * (1 + 1e-9)
    assert opened.max() > 0.5 * snaps[0].max()
    assert run.stats["steps"] > 0 and run.stats["contact_onsets"] >= s["contact_onsets"]


def test_the_same_scene_runs_to_the_same_bits_twice(short_run):
    again = short(jointwear.Scene.load(STANDARD)).run()
    assert list(again.timeseries) == list(short_run.timeseries)
    for name, column in short_run.timeseries.items():
        assert np.array_equal(column.view(np.uint64), again.timeseries[name].view(np.uint64))
    assert np.array_equal(short_run.wear["rod-slider"], again.wear["rod-slider"])
    assert short_run.stats == again.stats


def test_runs_release_the_gil():
    scene = jointwear.Scene.load(STANDARD).set("run.rotations", 40).set("run.record_rotations", 0)
    result = {}
    worker = threading.Thread(target=lambda: result.update(run=scene.run()))
    ticks = 0
    start = time.perf_counter()
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.002)
    worker.join()
    elapsed = time.perf_counter() - start
    # A run that held the GIL would block this loop for its whole length (one or two ticks);
    # released, the loop ticks every few milliseconds while the run goes on. Checked by
    # injection: without `py.detach` in Document::run this loop ticked once in a 0.9 s run.
    assert result["run"].wall_time_s > 0.05
    assert ticks >= 0.25 * elapsed / 0.002, (ticks, elapsed)


@pytest.mark.parametrize("call", ["run", "ensemble", "sweep"])
def test_ctrl_c_stops_a_call_within_a_rotation_and_the_scene_stays_usable(call):
    # 1000 rotations take over 5 s uninterrupted (an ensemble or a sweep: more).
    scene = jointwear.Scene.load(STANDARD).set("run.rotations", 1000).set("run.record_rotations", 0)
    calls = {
        "run": lambda: scene.run(),
        "ensemble": lambda: scene.ensemble(4),
        # (A sweep's rows need a recorded rotation: it refuses run.record_rotations = 0.)
        "sweep": lambda: scene.set("run.record_rotations", 1).sweep(
            {"driver.speed_rpm": [1500, 2000]}
        ),
    }
    # As Ctrl-C does: a real signal arrives while the call waits, outside Python code, and its
    # handler raises KeyboardInterrupt. (A timer thread calling _thread.interrupt_main needs the
    # GIL to fire: on a loaded machine it was not scheduled before the call ended, 3 failures.)
    previous = signal.signal(signal.SIGALRM, signal.default_int_handler)
    start = time.perf_counter()
    signal.setitimer(signal.ITIMER_REAL, 0.3)
    try:
        with pytest.raises(KeyboardInterrupt):
            calls[call]()
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    # Checked by injection: without the signal polling of `interruptible` the call ran to
    # its end (no KeyboardInterrupt until it returned, after seconds).
    assert time.perf_counter() - start < 1.5
    assert short(scene).run().wall_time_s > 0


def test_to_pandas_frames(short_run):
    pd = pytest.importorskip("pandas")
    frame = short_run.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == list(short_run.timeseries)
    assert len(frame) == 3001
    wear = short_run.to_pandas("wear")
    # the depth's column names its unit (it was the bare joint name)
    assert wear.index.name == "angle_deg" and list(wear.columns) == ["rod-slider.depth_m"]
    assert np.array_equal(wear["rod-slider.depth_m"].to_numpy(), short_run.wear["rod-slider"])
    snaps = short_run.to_pandas("snapshots")
    assert len(snaps) == 2 * 360
    summary = short_run.to_pandas("summary")
    assert summary.loc["rod-slider", "max_wear_depth_m"] == short_run.wear["rod-slider"].max()
    with pytest.raises(ValueError, match="unknown table"):
        short_run.to_pandas("nope")


def test_to_pandas_without_pandas_says_what_to_install(short_run, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now fails
    with pytest.raises(ImportError, match="Run.to_pandas\\(\\) needs pandas.*pip install pandas"):
        short_run.to_pandas()


def test_a_settling_run_counts_its_settling_rotations():
    """`Run.rotations` is what was simulated: it was the scene's `run.rotations` (3 here)
    while the wear and the whole-run values covered 10."""
    scene = jointwear.Scene.load(STANDARD)
    scene.set("run.rotations", 3).set("run.wear_snapshots", [1, 3]).set("run.record_rotations", 1)
    run = scene.set("run.settle", True).run()
    assert run.settling is not None
    assert run.rotations == run.settling["rotations"] + 3
    assert run.summary[run.joints[0]]["rotations_simulated"] == run.rotations


# Fails with the warnings in words of their own: the run's gave the orbit change to 3 digits
# (0.355 where the program prints 0.3552) and the ensemble's added to the program's line.
def test_unsettled_warnings_are_the_programs_lines(tmp_path, cli):
    capped = {
        "run.settle": True,
        "run.steady_state.max_rotations": 2,
        "run.steady_state.orbit_tolerance": 1e-9,
    }
    path = short_file(tmp_path, **capped)
    scene = jointwear.Scene.load(path)
    for flags, call in [([], scene.run), (["--ensemble", 2], lambda: scene.ensemble(2))]:
        with pytest.warns(RuntimeWarning, match="not settled") as warned:
            call()
        done = cli("run", path, *flags, "--out", tmp_path / f"out{len(flags)}")
        assert done.returncode == 0, done.stderr
        assert f"\n  {warned[0].message}\n" in done.stdout, (str(warned[0].message), done.stdout)


def test_the_summary_says_whether_the_run_settled():
    """`settled` tells a run that stopped at `steady_state.max_rotations` with its orbit still
    changing (0) from one that settled (1); a scene that does not settle has NaN."""
    scene = short(jointwear.Scene.load(STANDARD)).set("run.record_rotations", 1)
    assert np.isnan(scene.run().summary["rod-slider"]["settled"])
    scene.set("run.settle", True).set("run.steady_state.max_rotations", 2)
    # warned as `jointwear run` prints it (it passed without a word)
    with pytest.warns(RuntimeWarning, match="not settled: after 2 settling rotations"):
        capped = scene.set("run.steady_state.orbit_tolerance", 1e-9).run()
    assert capped.summary["rod-slider"]["settled"] == 0 and not capped.settling["steady"]
    with pytest.warns(RuntimeWarning, match="not settled: 2 of 2 members"):
        scene.ensemble(2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loose = scene.set("run.steady_state.orbit_tolerance", 1).run()
        scene.ensemble(2)
    assert loose.summary["rod-slider"]["settled"] == 1 and loose.settling["steady"]


def test_wear_of_joints_with_different_sector_counts_is_refused_naming_them():
    """One table cannot index them by angle; pandas' own length error named neither."""
    pytest.importorskip("pandas")
    scene = short(jointwear.Scene.load(SCENES / "two_clearance.toml"))
    run = scene.set("clearance.1.wear.sectors", 72).run()
    with pytest.raises(ValueError, match="different sector counts") as e:
        run.to_pandas("wear")
    assert all(name in str(e.value) for name in run.joints)
