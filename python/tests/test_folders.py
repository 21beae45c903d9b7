"""Run.save and Ensemble.save write the program's folder byte for byte, and ensembles and
sweeps spread over any concurrent.futures.Executor give bit for bit the default's results."""

import csv
import io
import json
import math
import multiprocessing
import os
import pickle
import shutil
import struct
from concurrent.futures import Executor, Future, ProcessPoolExecutor

import numpy as np
import pytest

import jointwear

from conftest import PAPER_OUTPUTS, STANDARD, short, short_file

# The changes both sides make: `--set run.record_rotations=1 --rotations 2` and the same `set`s
# in the same order (the rotations last, as the program applies them), so that the folders
# name the same command line and list the same changes.
CHANGES = [("run.record_rotations", 1), ("run.rotations", 2)]
PROGRAM_CHANGES = ["--set", "run.record_rotations=1", "--rotations", "2"]


def scene():
    s = jointwear.Scene.load(STANDARD)
    for key, value in CHANGES:
        s.set(key, value)
    return s


def spawning_pool():
    """Two worker processes started by spawn: a forked worker would inherit this process's
    thread pool without its threads."""
    return ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn"))


def without_wall_times(name, data):
    """The file `name` with the wall times left out: they are measured, so two runs never
    share them (summary.json's `wall_time_s`, ensemble_members.csv's column `wall_time_s`).
    Every other byte of every file must be the same."""
    if name == "summary.json":
        summary = json.loads(data)
        assert isinstance(summary.pop("wall_time_s"), float)
        return summary
    if name == "ensemble_members.csv":
        rows = list(csv.reader(io.StringIO(data.decode())))
        wall = rows[0].index("wall_time_s")
        return [row[:wall] + row[wall + 1 :] for row in rows]
    return data


def assert_same_folder(program, python):
    names = sorted(p.name for p in program.iterdir())
    assert names == sorted(p.name for p in python.iterdir())
    assert "jointwear-manifest.txt" in names and "README.txt" in names
    for name in names:
        a = without_wall_times(name, (program / name).read_bytes())
        b = without_wall_times(name, (python / name).read_bytes())
        assert a == b, name


# Fails when Python's folder names another command line (the rotations set before the recorded
# rotations: `--rotations 2 --set …` in README.txt and the manifest), when the member's flags
# are left out, or when the program and Python write different files; the perturbation cases
# fail when Python drops the protocol (checked: passing None for it natively gives other wear
# and another README.txt).
@pytest.mark.parametrize(
    "flags, run",
    [
        ([], lambda s: s.run()),
        (["--member", "1", "--seed", "5"], lambda s: s.run(member=1, seed=5)),
        (["--ensemble", "3", "--seed", "5"], lambda s: s.ensemble(3, seed=5)),
        (
            ["--member", "1", "--seed", "5", "--perturbation", "axis_10nm"],
            lambda s: s.run(member=1, seed=5, perturbation="axis_10nm"),
        ),
        (
            ["--ensemble", "3", "--seed", "5", "--perturbation", "velocity_10um_s"],
            lambda s: s.ensemble(3, seed=5, perturbation="velocity_10um_s"),
        ),
    ],
    ids=["run", "member", "ensemble", "member-perturbation", "ensemble-perturbation"],
)
def test_save_writes_the_programs_folder(tmp_path, cli, flags, run):
    done = cli("run", STANDARD, *PROGRAM_CHANGES, *flags, "--out", tmp_path / "program")
    assert done.returncode == 0, done.stderr
    result = run(scene())
    result.save(tmp_path / "python")
    assert_same_folder(tmp_path / "program", tmp_path / "python")
    # a member run says which member it is, as its summary.json does (it did not say)
    if isinstance(result, jointwear.Run):
        summary = json.loads((tmp_path / "program" / "summary.json").read_text())
        assert result.ensemble_member == summary["ensemble_member"]


# Fails without the scene saved: the folder of a scene built from a dict named the command
# `jointwear run <dict> …`, which no one can run, and held no copy of the scene.
@pytest.mark.parametrize(
    "run",
    [lambda s: s.run(), lambda s: s.run(member=1, seed=5), lambda s: s.ensemble(2, seed=5)],
    ids=["run", "member", "ensemble"],
)
def test_a_dict_scenes_folder_reruns_with_its_recorded_command(tmp_path, cli, run):
    data = {"extends": STANDARD.name, "title": "A scene from a dict"}
    s = jointwear.Scene.from_dict(data, base_dir=STANDARD.parent)
    for key, value in CHANGES:
        s.set(key, value)
    run(s).save(tmp_path / "python")
    manifest = (tmp_path / "python" / "jointwear-manifest.txt").read_text()
    command = manifest.splitlines()[0].removeprefix("# ")
    words = command.split(" ")
    assert words[:3] == ["jointwear", "run", str(tmp_path / "python" / "scene.toml")], command
    assert "scene.toml" not in manifest.splitlines()[1:], "the scene is not an output"
    done = cli(*words[1:], "--out", tmp_path / "program")
    assert done.returncode == 0, done.stderr
    (tmp_path / "python" / "scene.toml").rename(tmp_path / "scene.toml")
    # the same files, bit for bit, summary.json's scene path and fingerprint included
    assert_same_folder(tmp_path / "program", tmp_path / "python")


# Fails without the check: save of a dict scene replaced a scene.toml of the user's in the
# directory given.
def test_a_dict_scenes_save_keeps_another_scene_toml(tmp_path):
    s = short(jointwear.Scene.from_dict({"extends": str(STANDARD)}))
    mine = tmp_path / "scene.toml"
    mine.write_text('title = "mine"\n')
    with pytest.raises(jointwear.SceneError, match="without another scene's scene.toml") as e:
        s.run().save(tmp_path)
    assert "`directory`" in str(e.value)
    assert mine.read_text() == 'title = "mine"\n' and sorted(tmp_path.iterdir()) == [mine]
    # an earlier save's own scene is replaced by the next save's
    s.run().save(tmp_path / "out")
    other = short(jointwear.Scene.from_dict({"extends": str(STANDARD), "title": "other"}))
    other.run().save(tmp_path / "out")
    assert 'title = "other"' in (tmp_path / "out" / "scene.toml").read_text()


# Fails on the manifest's word: a folder the program ran the user's own scene.toml into
# (`jointwear run D/scene.toml --out D`) names that file in its manifest's command line, as a
# save's does, and the save of a dict scene replaced the user's scene by its own.
def test_a_dict_scenes_save_keeps_the_scene_toml_a_program_ran(tmp_path, cli):
    mine = tmp_path / "scene.toml"
    mine.write_text(short_file(tmp_path, "short.toml").read_text() + "# my notes\n")
    done = cli("run", mine, "--out", tmp_path)
    assert done.returncode == 0, done.stderr
    before = mine.read_text()
    s = short(jointwear.Scene.from_dict({"extends": str(STANDARD), "title": "other"}))
    with pytest.raises(jointwear.SceneError, match="without another scene's scene.toml"):
        s.run().save(tmp_path)
    assert mine.read_text() == before


# Fails with the mark alone: the scene.toml of an earlier save whose line ends were turned
# into CRLF, or one saved before the mark (this very scene, without it), was refused as the
# user's own.
def test_a_dict_scenes_save_replaces_its_earlier_saves_scene_toml(tmp_path):
    s = short(jointwear.Scene.from_dict({"extends": str(STANDARD)}))
    saved = tmp_path / "scene.toml"
    s.run().save(tmp_path)
    mark, rest = saved.read_text().split("\n", 1)
    assert mark.startswith("# ")
    saved.write_bytes(saved.read_bytes().replace(b"\n", b"\r\n"))
    other = short(jointwear.Scene.from_dict({"extends": str(STANDARD), "title": "other"}))
    other.run().save(tmp_path)
    assert 'title = "other"' in saved.read_text()
    s.run().save(tmp_path)
    saved.write_text(rest)
    s.run().save(tmp_path)
    assert saved.read_text() == mark + "\n" + rest


# Fails when the member is handed over as TOML, whose integers stop at 2^63 - 1.
def test_a_member_run_names_a_seed_beyond_63_bits():
    member = scene().run(member=0, seed=2**64 - 1).ensemble_member
    assert (member["member"], member["seed"]) == (0, 2**64 - 1)
    assert jointwear.Scene.load(STANDARD).set("run.rotations", 1).run().ensemble_member is None


def test_an_ensemble_on_an_executor_saves_the_programs_folder(tmp_path, cli):
    done = cli("run", STANDARD, *PROGRAM_CHANGES, "--ensemble", "3", "--seed", "5",
               "--out", tmp_path / "program")
    assert done.returncode == 0, done.stderr
    with spawning_pool() as pool:
        scene().ensemble(3, seed=5, executor=pool).save(tmp_path / "python")
    assert_same_folder(tmp_path / "program", tmp_path / "python")


def test_an_ensemble_on_an_executor_keeps_its_perturbation(tmp_path, cli):
    flags = ["--ensemble", "3", "--seed", "5", "--perturbation", "tolerance_1e-3"]
    done = cli("run", STANDARD, *PROGRAM_CHANGES, *flags, "--out", tmp_path / "program")
    assert done.returncode == 0, done.stderr
    with spawning_pool() as pool:
        ens = scene().ensemble(3, seed=5, executor=pool, perturbation="tolerance_1e-3")
    assert ens.perturbation == "tolerance_1e-3"
    ens.save(tmp_path / "python")
    assert_same_folder(tmp_path / "program", tmp_path / "python")


def test_a_bad_perturbation_names_the_protocols():
    s = scene()
    for call in (
        lambda: s.run(member=0, perturbation="disk_10nm"),
        lambda: s.ensemble(2, perturbation="disc_-1nm"),
        lambda: s.ensemble(2, perturbation="tolerance_1"),
    ):
        forms = "disc_<R>nm, axis_<R>nm, velocity_<V>um_s or tolerance_<S>"
        with pytest.raises(ValueError, match=forms):
            call()
    with pytest.raises(ValueError, match="member=K"):
        s.run(perturbation="axis_10nm")
    with pytest.raises(TypeError, match="perturbation"):
        s.ensemble(2, perturbation=10e-9)


def test_save_refuses_a_folder_another_process_writes(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".jointwear.lock").write_text("pid=1\nhost=elsewhere\ncommand=jointwear run other\n")
    with pytest.raises(jointwear.SceneError, match="jointwear run other") as refused:
        short(jointwear.Scene.load(STANDARD)).run().save(out)
    assert "`directory`" in str(refused.value) and "choose another directory" in str(
        refused.value
    )


# Fails without the claim in Folder.save: a save into the crate's figures/ or data/ (the
# package built from this checkout) wrote beside a running paper program, which could replace
# the folder's files or they its own, and returned normally; the program's commands refused.
# (Under the session's output root, JOINTWEAR_OUTPUT_ROOT: the checkout's lock and data/ were
# written, colliding with a paper program or another test run.)
def test_save_among_the_paper_outputs_waits_for_no_paper_program(short_run):
    lock = PAPER_OUTPUTS / ".paper-outputs.lock"
    out = PAPER_OUTPUTS / "data" / f"save-test-{os.getpid()}"
    host = open("/proc/sys/kernel/hostname").read().strip()
    # This live process holds the outputs, as a paper program would (never over a real one's).
    with open(lock, "x") as held:
        held.write(f"pid={os.getpid()}\nhost={host}\ncommand=fig06\n")
    try:
        with pytest.raises(jointwear.SceneError) as refused:
            short_run.save(out)
        assert not out.exists()
    finally:
        lock.unlink()
        shutil.rmtree(out, ignore_errors=True)
    message = str(refused.value)
    for needle in ("`directory`", "figures/, data/ and paper.md", "process", "`fig06`",
                   "choose another directory"):
        assert needle in message, message
    # Once no program holds them, the save claims them while it writes, then releases them.
    try:
        short_run.save(out)
        assert (out / "jointwear-manifest.txt").exists()
        assert not lock.exists()
    finally:
        shutil.rmtree(out, ignore_errors=True)


# Fails without the check in Folder.save: the refusal came from the writer, naming the
# "output folder" and giving the command line's advice (each command's default folder), which
# a Python caller cannot follow.
def test_save_refuses_another_commands_folder_naming_its_own_argument(tmp_path):
    s = short(jointwear.Scene.load(STANDARD))
    run, ens = s.run(), s.ensemble(2)
    ens.save(tmp_path / "ensemble")
    before = {p.name: p.read_bytes() for p in (tmp_path / "ensemble").iterdir()}
    for result, folder, holder in [
        (run, "ensemble", "`jointwear run --ensemble`"),
        (ens, "run", "`jointwear run`"),
    ]:
        if folder == "run":
            run.save(tmp_path / "run")
        with pytest.raises(jointwear.SceneError) as refused:
            result.save(tmp_path / folder)
        message = str(refused.value)
        assert f"`directory`: {tmp_path / folder}" in message, message
        assert f"holds the outputs of {holder}" in message, message
        assert "call save with another directory" in message, message
        assert "output folder" not in message and "out/<scene stem>" not in message, message
    assert {p.name: p.read_bytes() for p in (tmp_path / "ensemble").iterdir()} == before


# Fails without the check: save wrote its results beside the checkpoint of another process's
# unfinished run (its --resume would then replace them), returning normally.
def test_save_refuses_a_folder_holding_an_unfinished_runs_checkpoint(tmp_path, cli):
    out = tmp_path / "out"
    # the step limit stops the run in its third rotation, its last checkpoint kept
    done = cli("run", STANDARD, "--rotations", 5, "--checkpoint-every", 1,
               "--set", "run.max_steps=5000", "--out", out)
    assert done.returncode == 1 and (out / "checkpoint.json").exists(), done.stderr
    s = short(jointwear.Scene.load(STANDARD))
    for result in (s.run(), s.ensemble(2)):
        with pytest.raises(jointwear.SceneError, match="checkpoint of an unfinished run") as e:
            result.save(out)
        assert "`directory`" in str(e.value) and "--resume" in str(e.value)
        assert sorted(p.name for p in out.iterdir()) == ["checkpoint.json"]


# Fails without the notes routed: the lock's notes went to the process's stderr, which a
# notebook does not show, and not to sys.stderr.
def test_save_notes_a_stale_lock_on_sys_stderr(tmp_path, capsys):
    run = short(jointwear.Scene.load(STANDARD)).run()
    capsys.readouterr()
    # a holder of this host that is gone (a pid beyond Linux's largest, 2^22), killed while
    # writing a temporary file
    host = open("/proc/sys/kernel/hostname").read().strip()
    (tmp_path / ".jointwear.lock").write_text(f"pid=4194305\nhost={host}\ncommand=x\n")
    (tmp_path / ".wear.tmp-4194305-3.csv").write_text("x")
    run.save(tmp_path)
    err = capsys.readouterr().err
    assert "note: taking over " in err and "no longer runs" in err, err
    assert "note: removed 1 temporary file(s) that process 4194305 left" in err, err
    assert not (tmp_path / ".wear.tmp-4194305-3.csv").exists()


# Fails without the check: save("") wrote the run's folder into the working directory.
def test_save_refuses_an_empty_path(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run = short(jointwear.Scene.load(STANDARD)).run()
    with pytest.raises(jointwear.SceneError, match='`directory`: "" \\(expected a folder'):
        run.save("")
    assert list(tmp_path.iterdir()) == []
    # bad input, not a failure while running (it was a SimulationError, an I/O error)
    with pytest.raises(jointwear.SceneError, match="without a NUL character"):
        run.save("a\0b")
    assert list(tmp_path.iterdir()) == []


def bits(x):
    """`x` with every float as its bytes (NaN equal to NaN), for bit for bit comparisons."""
    if isinstance(x, float):
        return struct.pack("<d", x)
    if isinstance(x, np.ndarray):
        return (x.dtype.str, x.shape, x.tobytes())
    if isinstance(x, dict):
        return {k: bits(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [bits(v) for v in x]
    return x


def test_a_pickled_scene_is_the_scene():
    s = scene().set("clearance.0.clearance_mm", 0.4)
    copy = pickle.loads(pickle.dumps(s))
    assert copy.to_dict() == s.to_dict() and copy.path == s.path
    # the changes go along: setting the rotations again cuts nothing the user set
    assert copy.set("run.rotations", 1).to_dict() == s.set("run.rotations", 1).to_dict()


# Fails when a worker runs another member (the member numbers shifted by one) or another seed.
def test_an_ensemble_on_a_process_pool_is_bit_for_bit_the_ensemble():
    s = short(jointwear.Scene.load(STANDARD))
    default = s.ensemble(4, seed=3)
    with spawning_pool() as pool:
        spread = s.ensemble(4, seed=3, executor=pool)
    for name in ["scalars", "statistics", "motion_modes", "wear", "snapshots", "band"]:
        assert bits(getattr(spread, name)) == bits(getattr(default, name)), name


def sweep_columns(result):
    return {k: bits(v) for k, v in result.columns.items() if k != "wall_time_s"}


def test_a_sweep_on_a_process_pool_is_bit_for_bit_the_sweep():
    s = short(jointwear.Scene.load(STANDARD))
    grid = {"driver.speed_rpm": [-2000.0, -1500.0], "clearance.0.clearance_mm": [0.5, 0.4]}
    with spawning_pool() as pool:
        for members in (None, 2):
            default = s.sweep(grid, members=members)
            spread = s.sweep(grid, members=members, executor=pool)
            assert spread.errors == default.errors == [None] * 4
            assert sweep_columns(spread) == sweep_columns(default), members
            assert not any(math.isnan(x) for x in spread["wall_time_s"])


class Miswired(Executor):
    """Runs each task at once with its arguments changed by `rewire`: a worker that runs
    another member, or another scene, than the one it was sent."""

    def __init__(self, rewire):
        self.rewire = rewire

    def submit(self, fn, *args):
        future = Future()
        future.set_result(fn(*self.rewire(*args)))
        return future


# Fails without the check in ensemble_of: both ensembles were returned as the scene's, the
# first with its members in another order, the second pooling another scene's members.
def test_an_ensemble_refuses_results_of_another_member_or_scene():
    s = short(jointwear.Scene.load(STANDARD))
    other = s.copy().set("driver.speed_rpm", -1500.0)
    shifted = Miswired(lambda state, k, n, *rest: (state, (k + 1) % n, n, *rest))
    with pytest.raises(ValueError, match="member 0's result: it is member 1 of 3"):
        s.ensemble(3, executor=shifted)
    foreign = Miswired(lambda state, *rest: (other._doc.state(), *rest))
    with pytest.raises(ValueError, match="of the scene with fingerprint .* not member 0 of 3"):
        s.ensemble(3, executor=foreign)
    # the right wiring passes the check
    same = Miswired(lambda *args: args)
    assert bits(s.ensemble(3, executor=same).wear) == bits(s.ensemble(3).wear)


# Fails without the check in Scene.sweep: the shifted sweep returned normally with each row
# labelled by the case it ran (case 1 as row 0), the foreign one with another scene's rows
# under this sweep's values.
def test_a_sweep_refuses_results_of_another_case_or_sweep():
    s = short(jointwear.Scene.load(STANDARD))
    other = s.copy().set("clearance.0.clearance_mm", 0.05)
    grid = {"driver.speed_rpm": [-2000.0, -1500.0]}
    shifted = Miswired(lambda state, keys, values, k, *rest: (state, keys, values, 1 - k, *rest))
    with pytest.raises(ValueError, match="case 0's result is case 1 of the sweep"):
        s.sweep(grid, executor=shifted)
    foreign = Miswired(lambda state, *rest: (other._doc.state(), *rest))
    with pytest.raises(ValueError, match="not case 0 of this sweep"):
        s.sweep(grid, executor=foreign)
    same = Miswired(lambda *args: args)
    assert sweep_columns(s.sweep(grid, executor=same)) == sweep_columns(s.sweep(grid))


def test_an_executor_is_checked_at_the_call():
    s = short(jointwear.Scene.load(STANDARD))
    with pytest.raises(TypeError, match="executor must be a concurrent.futures.Executor"):
        s.ensemble(2, executor="pool")
    with pytest.raises(TypeError, match="executor"):
        s.sweep({"driver.speed_rpm": [-2000.0]}, executor=4)
    # a bad value is refused before any task is submitted
    with spawning_pool() as pool, pytest.raises(jointwear.SceneError, match="clearance_mm"):
        s.sweep({"clearance.0.clearance_mm": [-1.0]}, executor=pool)


def test_an_ensemble_on_a_local_dask_cluster_is_bit_for_bit_the_ensemble():
    distributed = pytest.importorskip(
        "distributed",
        reason="dask.distributed is not installed; the executor path is tested with a process pool",
    )
    s = short(jointwear.Scene.load(STANDARD))
    default = s.ensemble(3, seed=2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster:
        with distributed.Client(cluster) as client:
            spread = s.ensemble(3, seed=2, executor=client.get_executor())
    for name in ["scalars", "statistics", "wear", "band"]:
        assert bits(getattr(spread, name)) == bits(getattr(default, name)), name
