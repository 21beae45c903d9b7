"""Scenes: loaded from a file or a dict, varied by dotted keys, run, run as an ensemble or swept."""

from __future__ import annotations

import itertools
import numbers
import os
import time
import warnings
from collections.abc import Iterable
from concurrent.futures import Executor, Future
from typing import Any, List, Mapping, Optional, Sequence, Tuple, TypeVar, Union

from ._native import Document, SceneError
from ._results import Ensemble, Run, SweepResult, _path

PathLike = Union[str, "os.PathLike[str]"]
Result = TypeVar("Result", Run, Ensemble)


def _count(name: str, value: Any, expected: str) -> int:
    """``value`` as an int the native call takes (0 to 2**64 - 1, whose own range it then
    checks), or TypeError/SceneError naming the argument: ``int(2.5)`` would silently run 2
    members, and a negative count raised OverflowError."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {value!r} ({type(value).__name__})")
    if not 0 <= value < 2**64:
        raise SceneError(f"invalid value for `{name}`: {value} (expected {expected})")
    return int(value)


class Scene:
    """A scene: a mechanism with clearance joints and its run settings.

    Create one with :meth:`Scene.load` or :meth:`Scene.from_dict`; both validate it at once and
    raise :class:`jointwear.SceneError` with the ``jointwear`` program's message if it is bad.
    """

    __slots__ = ("_doc",)

    def __init__(self, document: Document) -> None:
        self._doc = document

    def __reduce__(self):
        # Pickled as text (the document as loaded and the changes set on it), so that an
        # executor's worker process gets an identical scene.
        return (_restore, self._doc.state())

    @classmethod
    def load(cls, path: PathLike) -> "Scene":
        """Reads and validates the scene file at ``path`` (``extends`` and ``[overrides]``
        resolved), as ``jointwear run`` does."""
        return cls(Document.load(_path("path", path)))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], base_dir: Optional[PathLike] = None) -> "Scene":
        """A scene from a dict with the keys of a scene file (the same names and units, e.g.
        ``{"title": ..., "run": {"rotations": 2, ...}, ...}``), validated at once.

        Messages name it ``<dict>``; ``base_dir`` is where a relative ``extends`` is found
        (default: the working directory), so ``{"extends": "standard.toml", "overrides":
        {...}}`` works as in a file. :meth:`Run.save` and :meth:`Ensemble.save` write it to
        ``scene.toml`` in their folder, whose command line names that file.
        """
        # (dict() of a list of pairs made a scene of it; of other lists, a message about
        # "dictionary update sequence elements")
        if not isinstance(data, Mapping):
            raise TypeError(
                f"data must be a dict of a scene file's keys, got {type(data).__name__}"
            )
        base = _path("base_dir", base_dir) if base_dir is not None else None
        return cls(Document.from_dict(dict(data), base))

    def set(self, key: str, value: Any) -> "Scene":
        """Sets the value at a dotted ``key`` (``"clearance.0.clearance_mm"``,
        ``"driver.speed_rpm"``, ``"run.wear_snapshots"``) as the program's ``--set`` does, with
        Python values (bool, int, float, str, list, dict, numpy scalars). Returns the scene, so
        calls chain. A key that the scene file cannot have, or a value of the wrong type,
        raises :class:`jointwear.SceneError` now and leaves the scene as it was; a value out of
        range raises when the scene is next checked or run. ``set("run.rotations", n)`` drops
        the wear snapshots past ``n`` and cuts ``run.record_rotations`` to ``n``, as the
        program's ``--rotations`` does, unless they were set on this scene (a note on
        ``sys.stderr`` says what it changed). A value that turns the driver the other way than
        the scene as loaded (the shipped scenes are calibrated in their own sense) writes a
        note on ``sys.stderr``. Setting a key set before (under any spelling,
        ``clearance.00.clearance_mm`` for ``clearance.0.clearance_mm``) replaces that change:
        the scene is the one set each key once, with its last value, as the command line a
        saved folder records (which the program refuses with a key given twice)."""
        if not isinstance(key, str):
            raise TypeError(f"key must be a dotted key (str), got {key!r}")
        self._doc.set(key, value)
        return self

    def copy(self) -> "Scene":
        """An independent copy (``set`` on it leaves this scene unchanged)."""
        return Scene(self._doc.copy())

    def to_dict(self) -> dict:
        """The scene as a dict of the keys of a scene file (``extends`` resolved)."""
        return self._doc.to_dict()

    @property
    def path(self) -> str:
        """The file the scene came from (``<dict>`` for a dict), as messages name it."""
        return os.fspath(self._doc.path)

    @property
    def title(self) -> str:
        """The scene's title."""
        return self.to_dict()["title"]

    def check(self) -> dict:
        """Validates and assembles the scene and turns its driver through one rotation as
        ``jointwear check`` does (a loop that cannot close at some driver angle is a
        :class:`SceneError` naming the angles and the joints). Returns its
        ``title``, ``bodies``, clearance ``joints`` (``name``, ``clearance_m``,
        ``bearing_radius_m``, ``sectors`` or None without wear, and the contact law's
        ``stiffness`` and ``dissipation`` in the scene spelling, e.g. ``"hybrid"`` and
        ``"zhiying-qishao"`` for ``model = "hybrid"``), ``dof``, ``period_s`` (of the
        driver) and ``rotations``."""
        return self._doc.check()

    def run(
        self, member: Optional[int] = None, seed: int = 1, perturbation: Optional[str] = None
    ) -> Run:
        """Simulates the scene (the GIL is released meanwhile) and returns the :class:`Run`:
        the same numbers, bit for bit, as ``jointwear run``. With ``member``, runs member
        ``member`` (0-based) of ``ensemble(members, seed, perturbation)`` instead, bit for bit
        the member the ensemble ran (``jointwear run --member K --seed S --perturbation P``); a
        member beyond the largest ensemble raises :class:`jointwear.SceneError`.
        ``perturbation`` (only with ``member``) is a protocol as :meth:`ensemble` takes it. A
        settling run that stops at ``run.steady_state.max_rotations`` unsettled warns
        (RuntimeWarning), as the program prints it: its recorded rotations are no steady
        state."""
        if member is not None:
            member = _count("member", member, "an integer in [0, 2^64)")
        seed = _count("seed", seed, "an integer in [0, 2^64)")
        return _noting_unsettled(Run(self._doc.run(member, seed, _protocol(perturbation))))

    def ensemble(
        self,
        members: int = 32,
        seed: int = 1,
        executor: Optional[Executor] = None,
        perturbation: Optional[str] = None,
    ) -> Ensemble:
        """Runs ``members`` copies of the scene in parallel, each perturbed by a seeded draw
        (``jointwear run --ensemble N --seed S --perturbation P``), and returns the
        :class:`Ensemble`: every member's results and their statistics. Single runs are
        chaotic; statistics over an ensemble are the project's results, and how members are
        perturbed can shift them (paper.md, the perturbation study). Members that stop
        settling at ``run.steady_state.max_rotations`` are counted in a RuntimeWarning, as the
        program prints them.

        ``perturbation``: the protocol, named as the program's ``--perturbation`` and the
        perturbation study name it: ``"disc_<R>nm"`` (every journal displaced uniformly over a
        disc of R nm, the default ``"disc_10nm"``), ``"axis_<R>nm"`` (along one body axis
        only), ``"velocity_<V>um_s"`` (journal centred, its initial velocity perturbed) or
        ``"tolerance_<S>"`` (journal centred, the tolerances jittered by a factor in [1 - S,
        1 + S]); any other value raises ValueError naming these forms.

        ``executor``: any :class:`concurrent.futures.Executor` (a process pool, a
        ``dask.distributed`` client's ``get_executor()``, a Ray pool's executor) runs one task
        per member instead of this process's threads; each task gets the scene as text and the
        member's number, and the results are bit for bit those without it (but the wall
        times). A member that fails raises its error here; a result that is not the member
        asked for (another member, scene or build of jointwear) raises ValueError."""
        members = _count("members", members, "a positive integer")
        seed = _count("seed", seed, "an integer in [0, 2^64)")
        protocol = _protocol(perturbation)
        if executor is None:
            return _noting_unsettled(Ensemble(self._doc.ensemble(members, seed, protocol)))
        _check_executor(executor)
        self._doc.check_ensemble(members, seed, protocol)
        started = time.perf_counter()
        state = self._doc.state()
        tasks = [
            executor.submit(_member, state, k, members, seed, protocol) for k in range(members)
        ]
        payloads = _gather(tasks)
        wall = time.perf_counter() - started
        ensemble = Ensemble(self._doc.ensemble_of(members, seed, payloads, wall, protocol))
        return _noting_unsettled(ensemble)

    def sweep(
        self,
        grid: Mapping[str, Sequence[Any]],
        members: Optional[int] = None,
        seed: int = 1,
        executor: Optional[Executor] = None,
    ) -> SweepResult:
        """Runs the cartesian product of the values of ``grid`` (dotted key -> values; the last
        key varies fastest, as in ``jointwear sweep``) in parallel, each case once or as an
        ensemble of ``members`` (perturbed by the default protocol, ``disc_10nm``, from
        ``seed``, as ``jointwear sweep --ensemble N --seed S``). Every value of every key is
        validated before any case runs (a bad value raises :class:`jointwear.SceneError`), and
        so are the keys (one given twice, also as an alias such as
        ``clearance.00.clearance_mm``, is refused, and so is a value given twice for one key,
        such as ``[0.1, 1e-1]``) and the size (at most 1 000 000 cases);
        cases are built as they run, and one that records no rotation
        (``run.record_rotations`` 0) is refused, as a row reports the recorded rotations. A case
        that fails to build or while running has its message in the ``error`` column and the
        others go on. Ctrl-C stops the sweep and raises KeyboardInterrupt: no partial result
        is returned (``jointwear sweep --out F --resume`` keeps the finished cases of an
        interrupted sweep).

        ``executor``: any :class:`concurrent.futures.Executor` runs one task per case instead
        of this process's threads (see :meth:`ensemble`); every value is validated here before
        any task is submitted, and the results are bit for bit those without it (but the wall
        times); a result that is not the case asked for (another case, scene or build of
        jointwear) raises ValueError."""
        if not isinstance(grid, Mapping):
            raise TypeError(
                f"grid must be a dict of dotted key -> values, got {type(grid).__name__}"
            )
        keys = list(grid)
        values = []
        for key in keys:
            if not isinstance(key, str):
                raise TypeError(f"grid keys must be dotted keys (str), got {key!r}")
            v = grid[key]
            # (A mapping iterates its keys: {-600: 1} swept -600 without a word.)
            if isinstance(v, (str, bytes, Mapping)) or not isinstance(v, Iterable):
                raise TypeError(
                    f"sweep values must be a sequence: {key!r} has {v!r}; "
                    f"write [{v!r}] for a single value"
                )
            values.append(list(v))
        if members is not None:
            members = _count("members", members, "a positive integer")
        seed = _count("seed", seed, "an integer in [0, 2^64)")
        # (Both calls give back the keys as the program's sweep header spells them: an alias
        # such as clearance.00.clearance_mm as clearance.0.clearance_mm.)
        if executor is None:
            keys, cases = self._doc.sweep(keys, values, members, seed)
        else:
            _check_executor(executor)
            keys, total, identity = self._doc.check_sweep(keys, values, members, seed)
            state = self._doc.state()
            tasks = [
                executor.submit(_case, state, keys, values, k, members, seed) for k in range(total)
            ]
            cases = _gather(tasks)
            for k, case in enumerate(cases):
                # A case of another sweep (a worker of another build or scene) or another
                # case than asked would be labelled with this one's values.
                ran = (case.pop("sweep", None), case.get("case"))
                if ran != (identity, k):
                    raise ValueError(
                        f"case {k}'s result is case {ran[1]} of the sweep {ran[0]!r}, not "
                        f"case {k} of this sweep ({identity!r}); likely cause: a worker of "
                        "another build of jointwear, or tasks gathered out of order"
                    )
        combos = list(itertools.product(*values))
        return SweepResult(keys, combos, cases, members)

    def __repr__(self) -> str:
        return f"Scene({self.title!r}, path={self.path!r})"


def _noting_unsettled(result: Result) -> Result:
    """``result`` (a :class:`Run` or :class:`Ensemble`), with a RuntimeWarning where it, or
    some of its members, stopped settling at ``run.steady_state.max_rotations``, in the words
    ``jointwear run`` prints: their recorded rotations are no steady state."""
    if result._unsettled is not None:
        warnings.warn(result._unsettled, RuntimeWarning, stacklevel=3)
    return result


def _protocol(perturbation: Any) -> Optional[str]:
    """``perturbation`` as the native calls take it (None: the default protocol), or TypeError
    naming the argument; its value is checked there (ValueError naming the forms allowed)."""
    if perturbation is not None and not isinstance(perturbation, str):
        raise TypeError(
            f"perturbation must be a protocol name such as 'disc_10nm', got {perturbation!r} "
            f"({type(perturbation).__name__})"
        )
    return perturbation


def _check_executor(executor: Any) -> None:
    """TypeError naming the argument unless ``executor`` has ``submit`` (an Executor)."""
    if not callable(getattr(executor, "submit", None)):
        raise TypeError(
            f"executor must be a concurrent.futures.Executor, got {executor!r} "
            f"({type(executor).__name__})"
        )


def _gather(tasks: List[Future]) -> List[Any]:
    """The results of ``tasks`` in order. On the first failure (or Ctrl-C) the tasks not yet
    started are cancelled, so that a failed ensemble does not go on running, and the error is
    raised."""
    try:
        return [task.result() for task in tasks]
    except BaseException:
        for task in tasks:
            task.cancel()
        raise


# `Document.state()`: the path, the document as loaded (TOML) and the changes set on it.
State = Tuple[PathLike, str, List[Tuple[str, str, bool]]]


def _restore(path: PathLike, loaded: str, changes: List[Tuple[str, str, bool]]) -> Scene:
    """The scene of ``Document.state()``: how a pickled :class:`Scene` is rebuilt."""
    return Scene(Document.from_state(path, loaded, changes))


def _member(
    state: State, member: int, members: int, seed: int, perturbation: Optional[str]
) -> str:
    """An executor's task: member ``member`` of an ensemble, as JSON for ``ensemble_of``."""
    return Document.from_state(*state).member(member, members, seed, perturbation)


def _case(
    state: State,
    keys: List[str],
    values: List[List[Any]],
    case: int,
    members: Optional[int],
    seed: int,
) -> dict:
    """An executor's task: case ``case`` of a sweep, as ``Document.sweep`` gives it."""
    return Document.from_state(*state).sweep_case(keys, values, case, members, seed)
