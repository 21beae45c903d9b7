"""Results as numpy arrays: one run, an ensemble, a sweep; ``to_pandas()`` where pandas is
installed."""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

PathLike = Union[str, "os.PathLike[str]"]


def _path(name: str, value: Any) -> str:
    """``value`` (a str, bytes or os.PathLike) as the str path the native calls take, or
    TypeError naming the argument: bytes paths raised "'bytes' object is not an instance of
    'str'"."""
    try:
        return os.fsdecode(value)
    except TypeError:
        raise TypeError(
            f"{name} must be a path (str or os.PathLike), got {value!r} "
            f"({type(value).__name__})"
        ) from None


def _array(data: bytes) -> np.ndarray:
    """A writable float64 array of the native-endian bytes the extension hands over."""
    return np.frombuffer(data, dtype=np.float64).copy()


def _pandas(what: str):
    """pandas, or an ImportError that says what needs it."""
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            f"{what} needs pandas, which is not installed: pip install pandas "
            "(the numpy arrays need nothing more)"
        ) from e
    return pandas


class Run:
    """The results of one run, in SI units.

    Attributes:
        title: the scene's title.
        rotations: driver rotations simulated, settling included (the scene's
            ``run.rotations`` after the settling rotations of :attr:`settling`, if any).
        period_s: driver period (s).
        wall_time_s: wall-clock time of the run (s).
        timeseries: column name -> array over the recorded rotations: the columns of
            ``jointwear run``'s ``timeseries.csv`` (``time_s``, ``driver_angle_rad``, per
            clearance joint ``<joint>.ex_m`` ... ``.wear_rate_m_s`` with the contact angle
            ``<joint>.contact_angle_deg`` in the bearing frame, per body ``<body>.ax_m_s2``
            ...; units, frames and signs in the ``README.txt`` that ``jointwear run`` writes),
            then every body's ``<body>.x_m``, ``.y_m``, ``.angle_rad``.
        joints: names of the clearance joints.
        angles_deg: joint -> sector centres of its wear profile (deg), for joints with wear.
        wear: joint -> final wear depth per sector (m), as ``wear_<joint>.csv``.
        snapshot_rotations: rotation counts of ``run.wear_snapshots``.
        snapshots: joint -> array (snapshot, sector) of wear depths (m).
        summary: joint -> dict: ``max_normal_force_recorded_n`` and
            ``max_penetration_recorded_m`` (over the recorded rotations; NaN when none were
            recorded), ``max_penetration_whole_run_m`` (over every accepted step from the
            start, at its end and at a peak inside it located on the integrator's dense output;
            the start-up transient and any settling included), ``max_wear_angle_deg``,
            ``max_wear_depth_m`` (angle and depth of the deepest sector), ``contact_fraction``,
            ``impacts_per_rotation`` and ``continuous_contact`` (1 or 0; these three over the
            recorded rotations), ``rotations_simulated`` (from the start, settling included: the
            window of the whole-run maximum, of the wear and of ``contact_onsets``), ``settled`` (1 if
            a settling run met its steady-state criterion, 0 if it stopped at
            ``steady_state.max_rotations`` with its orbit still changing, NaN for a scene that
            does not settle), ``motion_mode``,
            ``contact_onsets`` (the joint's contact onsets over the whole run, settling
            included, as ``summary.json`` of ``jointwear run`` counts them; not the recorded
            window of ``impacts_per_rotation``) and ``wear_regions`` (every wear region, most prominent first: ``angle_deg``,
            ``depth_m``, ``prominence_m``, ``width_deg``; the README's "Wear regions").
        stats: integrator counters over the whole run, settling included (``steps``,
            ``rejected``, ``evaluations``, ``contact_onsets`` of all joints), as ``counts`` in
            ``summary.json``.
        energy: with ``run.energy_accounting``, the energy account over the whole run from the
            start (J): ``driver_work_j``, ``normal_work_j`` (of the normal contact forces),
            ``friction_work_j`` (<= 0), ``mechanical_change_j`` (kinetic, gravitational and
            contact elastic), ``damping_loss_j``, and ``residual``, dimensionless: the driver
            work less the mechanical change and the losses, relative to the larger of the
            driver work and the mechanical change (``summary.json``'s
            ``energy_balance_residual``); else None.
        ensemble_member: for ``Scene.run(member=K, ...)``, the member the run is, as
            ``summary.json``'s ``ensemble_member``: ``member``, ``seed``, ``perturbation`` (the
            protocol's key), ``perturbation_description`` and ``tolerance_factor`` (the
            member's factor on the scene's rtol and atol); None for the scene's own start.
        settling: the settling phase of a scene with ``run.settle``, else None: ``rotations``
            (settling rotations), ``orbit_change`` (the last one's RMS orbit change over the
            clearance, dimensionless) and ``steady`` (False where
            ``steady_state.max_rotations`` was reached first), as in ``summary.json``.
    """

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.title: str = raw["title"]
        self.rotations: int = raw["rotations"]
        self.period_s: float = raw["period_s"]
        self.wall_time_s: float = raw["wall_time_s"]
        self.timeseries: Dict[str, np.ndarray] = {n: _array(b) for n, b in raw["columns"]}
        self.joints: List[str] = [j["name"] for j in raw["joints"]]
        self.snapshot_rotations = np.asarray(raw["snapshot_rotations"], dtype=np.int64)
        self.angles_deg: Dict[str, np.ndarray] = {}
        self.wear: Dict[str, np.ndarray] = {}
        self.snapshots: Dict[str, np.ndarray] = {}
        self.summary: Dict[str, Dict[str, Any]] = {}
        for j in raw["joints"]:
            name = j["name"]
            if "final_wear_m" in j:
                self.angles_deg[name] = _array(j["angle_deg"])
                self.wear[name] = _array(j["final_wear_m"])
                sectors = len(self.wear[name])
                self.snapshots[name] = _array(j["snapshots_m"]).reshape(-1, sectors)
            self.summary[name] = {
                k: v
                for k, v in j.items()
                if k not in ("name", "angle_deg", "final_wear_m", "snapshots_m")
            }
        self.stats: Dict[str, int] = raw["stats"]
        self.energy: Optional[Dict[str, float]] = raw["energy"]
        self.settling: Optional[Dict[str, Any]] = raw["settling"]
        self.ensemble_member: Optional[Dict[str, Any]] = raw["ensemble_member"]
        self._folder = raw["folder"]
        # The program's line for a run that stopped settling unsettled (Scene.run warns).
        self._unsettled: Optional[str] = raw["unsettled"]

    def save(self, directory: PathLike) -> None:
        """Writes the run's folder into ``directory`` as ``jointwear run`` writes its ``--out``
        folder, file for file and byte for byte (``timeseries.csv``, wear profiles and
        snapshots, figures, ``summary.json``, ``README.txt``, the manifest) but the wall time
        in ``summary.json``; its README and manifest name the command line that runs the same
        scene (``set("run.rotations", n)`` as ``--rotations n``). A scene built with
        :meth:`Scene.from_dict` is written, as built and before its changes, to
        ``directory/scene.toml``, beside the outputs and not in the manifest, and the command
        line names that file: running it gives the same files. The lock of a writer that no
        longer runs is taken over, and the temporary files it left removed, each with a note on
        ``sys.stderr``. Raises
        :class:`jointwear.SceneError`, writing nothing, if another process is writing into
        ``directory`` (or, for a ``directory`` among the paper's outputs of the checkout the
        package was built from, ``figures/`` or ``data/``, while a paper program writes
        them), if it holds the outputs of another command (an ensemble's folder, or
        ``jointwear longlife``'s), which this write would remove or overwrite, or if it holds
        the checkpoint of an unfinished ``jointwear run``, which would later replace them, or
        for a scene from a dict, if it holds another ``scene.toml`` than an earlier save's
        (whose first line says so)."""
        self._folder.save(_path("directory", directory))

    def to_pandas(self, table: str = "timeseries"):
        """A pandas DataFrame of ``table``: ``"timeseries"`` (one column per series),
        ``"wear"`` (index ``angle_deg``, one column ``<joint>.depth_m`` per joint of its final
        depth (m); joints with the same sector count), ``"snapshots"`` (long format: joint,
        rotation, angle_deg, depth_m) or ``"summary"`` (one row per joint, its scalar
        results). Raises ImportError if pandas is not installed."""
        pd = _pandas("Run.to_pandas()")
        if table == "timeseries":
            return pd.DataFrame(self.timeseries)
        if table == "wear":
            if not self.wear:
                return pd.DataFrame()
            sectors = {name: len(a) for name, a in self.angles_deg.items()}
            if len(set(sectors.values())) > 1:
                raise ValueError(
                    f"the joints' wear profiles have different sector counts ({sectors}): "
                    'one table cannot index them by angle; use Run.wear and Run.angles_deg, or '
                    'to_pandas("snapshots")'
                )
            first = next(iter(self.angles_deg.values()))
            # Named with their unit, as wear_<joint>.csv names its depth column.
            depths = {f"{name}.depth_m": depth for name, depth in self.wear.items()}
            return pd.DataFrame(depths, index=pd.Index(first, name="angle_deg"))
        if table == "snapshots":
            rows = []
            for name, snaps in self.snapshots.items():
                for rotation, depths in zip(self.snapshot_rotations, snaps):
                    for angle, depth in zip(self.angles_deg[name], depths):
                        rows.append((name, int(rotation), angle, depth))
            return pd.DataFrame(rows, columns=["joint", "rotation", "angle_deg", "depth_m"])
        if table == "summary":
            rows = {
                name: {k: v for k, v in s.items() if k != "wear_regions"}
                for name, s in self.summary.items()
            }
            return pd.DataFrame.from_dict(rows, orient="index").rename_axis("joint")
        raise ValueError(
            f"unknown table {table!r}: one of 'timeseries', 'wear', 'snapshots', 'summary'"
        )

    def __repr__(self) -> str:
        return (
            f"Run({self.title!r}, rotations={self.rotations}, joints={self.joints}, "
            f"samples={len(self.timeseries.get('time_s', ()))}"
            + (
                ""
                if self.ensemble_member is None
                else f", member={self.ensemble_member['member']}, "
                f"seed={self.ensemble_member['seed']}, "
                f"perturbation={self.ensemble_member['perturbation']!r}"
            )
            + ")"
        )


class Ensemble:
    """The members of an ensemble and their statistics.

    Attributes:
        title, wall_time_s: as for :class:`Run`.
        rotations: the scene's ``run.rotations``, which each member simulated after its own
            settling, if the scene settles (members settle in different numbers of
            rotations: each member's total is its ``rotations_simulated`` scalar).
        members: the member count; seed: the seed of their perturbations.
        perturbation: how the members were perturbed, the protocol as ``ensemble``'s
            ``perturbation`` names it (``"disc_10nm"`` by default), as ``summary.json`` names
            it: the statistics depend on it.
        joints: names of the clearance joints.
        scalar_names: the names of the per-member scalar results (as in :attr:`Run.summary`).
        scalars: joint -> name -> array (member,) of that result.
        motion_modes: joint -> list of each member's motion mode (None without a recording).
        statistics: joint -> name -> dict, as each quantity of ``summary.json`` has it: its
            ``window``, the part of each member's run it is taken over (``recorded``: the
            recorded rotations, which is also the window of ``contact_fraction``,
            ``impacts_per_rotation`` and ``continuous_contact``; ``whole_run``: every rotation
            from the start, settling included; ``settling``: the settling phase), ``n``
            (finite values), ``mean``, ``sd``, ``min``, ``q05``, ``q25``, ``q50``, ``q75``,
            ``q95``, ``max`` (angles unwrapped around their circular mean; NaN where ``n`` is
            0, ``summary.json``'s null), and the states the members fall into (largest-gap
            rule): ``states`` 1 or 2, and ``low_n``, ``low_mean``, ``low_sd``, ``high_n``,
            ``high_mean``, ``high_sd`` (the counts ints; None with one state; all seven None
            where ``n`` is 0). Angles are split too: cut at their largest gap on the circle,
            split only at a gap over 10 deg, low and high being the two sides of the cut (an
            ensemble whose members wear in two regions has both).
        angles_deg: joint -> sector centres (deg), for joints with wear.
        wear: joint -> array (member, sector) of final wear depths (m).
        snapshot_rotations: rotation counts of the wear snapshots.
        snapshots: joint -> array (member, snapshot, sector) of wear depths (m).
        band: joint -> statistic name (``mean``, ``sd``, ``min``, ``q05`` ... ``q95``,
            ``max``) -> array (sector,): the per-sector statistics of the final profiles'
            depths (m), as ``ensemble_wear_<joint>.csv`` (whose columns add ``_m``).
    """

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.title: str = raw["title"]
        self.members: int = raw["members"]
        self.seed: int = raw["seed"]
        self.perturbation: str = raw["perturbation"]
        self.rotations: int = raw["rotations"]
        self.wall_time_s: float = raw["wall_time_s"]
        self.scalar_names: List[str] = list(raw["scalar_names"])
        self.snapshot_rotations = np.asarray(raw["snapshot_rotations"], dtype=np.int64)
        self.joints: List[str] = [j["name"] for j in raw["joints"]]
        self.scalars: Dict[str, Dict[str, np.ndarray]] = {}
        self.statistics: Dict[str, Dict[str, Dict[str, Any]]] = {}
        self.motion_modes: Dict[str, List[Optional[str]]] = {}
        self.angles_deg: Dict[str, np.ndarray] = {}
        self.wear: Dict[str, np.ndarray] = {}
        self.snapshots: Dict[str, np.ndarray] = {}
        self.band: Dict[str, Dict[str, np.ndarray]] = {}
        n = self.members
        for j in raw["joints"]:
            name = j["name"]
            self.scalars[name] = {k: _array(b) for k, b in j["scalars"].items()}
            self.statistics[name] = j["statistics"]
            self.motion_modes[name] = list(j["motion_mode"])
            if "band" in j:
                angles = _array(j["angle_deg"])
                sectors = len(angles)
                self.angles_deg[name] = angles
                self.wear[name] = _array(j["final_wear_m"]).reshape(n, sectors)
                self.snapshots[name] = _array(j["snapshots_m"]).reshape(
                    n, len(self.snapshot_rotations), sectors
                )
                self.band[name] = {k: _array(b) for k, b in j["band"].items()}
        self._folder = raw["folder"]
        # The program's line for members that stopped settling unsettled (Scene.ensemble warns).
        self._unsettled: Optional[str] = raw["unsettled"]

    def save(self, directory: PathLike) -> None:
        """Writes the ensemble's folder into ``directory`` as ``jointwear run --ensemble N
        --seed S`` writes its ``--out`` folder, byte for byte but the wall times (in
        ``summary.json`` and the ``wall_time_s`` column of ``ensemble_members.csv``); see
        :meth:`Run.save`."""
        self._folder.save(_path("directory", directory))

    def mean_snapshot(self, joint: str, rotation: int) -> np.ndarray:
        """The mean over the members of the wear profile (m) of ``joint`` after ``rotation``
        rotations (one of :attr:`snapshot_rotations`)."""
        if joint not in self.snapshots:
            raise KeyError(
                f"no wear snapshots of joint {joint!r}: the joints with wear are "
                f"{list(self.snapshots)}"
            )
        hits = np.flatnonzero(self.snapshot_rotations == rotation)
        if len(hits) == 0:
            raise KeyError(
                f"no wear snapshot after {rotation} rotations: the scene's run.wear_snapshots "
                f"are {self.snapshot_rotations.tolist()}"
            )
        return self.snapshots[joint][:, hits[0], :].mean(axis=0)

    def to_pandas(self, table: str = "summary"):
        """A pandas DataFrame of ``table``: ``"summary"`` (one row per joint and quantity: its
        :attr:`statistics`, window first), ``"members"`` (one row per member, columns
        ``<joint>.<quantity>``) or ``"band"`` (one row per joint and sector: ``angle_deg`` and
        the per-sector statistics of the final wear depth, ``mean_m``, ``sd_m``, ``min_m``,
        ``q05_m`` ... ``q95_m``, ``max_m``, as ``ensemble_wear_<joint>.csv``). Raises
        ImportError if pandas is not installed."""
        pd = _pandas("Ensemble.to_pandas()")
        if table == "summary":
            rows = [
                {"joint": j, "quantity": q, **stats}
                for j, per in self.statistics.items()
                for q, stats in per.items()
            ]
            return pd.DataFrame(rows)
        if table == "members":
            columns: Dict[str, Any] = {}
            for j, per in self.scalars.items():
                for q, values in per.items():
                    columns[f"{j}.{q}"] = values
                columns[f"{j}.motion_mode"] = self.motion_modes[j]
            return pd.DataFrame(columns).rename_axis("member")
        if table == "band":
            frames = []
            for j, band in self.band.items():
                # Named with their unit, as the columns of ensemble_wear_<joint>.csv.
                depths = {f"{k}_m": v for k, v in band.items()}
                frame = pd.DataFrame({"angle_deg": self.angles_deg[j], **depths})
                frame.insert(0, "joint", j)
                frames.append(frame)
            return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
        raise ValueError(f"unknown table {table!r}: one of 'summary', 'members', 'band'")

    def __repr__(self) -> str:
        return (
            f"Ensemble({self.title!r}, members={self.members}, seed={self.seed}, "
            f"perturbation={self.perturbation!r}, rotations={self.rotations}, "
            f"joints={self.joints})"
        )


class SweepResult:
    """The cases of a sweep, one row each, in case order (the last key varying fastest).

    Attributes:
        keys: the swept dotted keys.
        members: the ensemble size of every case, or None for single runs.
        columns: column name -> array over the cases: ``case``, each swept key (its values as
            given), then the columns of ``jointwear sweep``'s file: ``members`` (ensembles),
            ``record_rotations`` and ``record_interval_s`` (the recorded rotations and the
            interval they were sampled on, s: the window of every recorded quantity), per joint
            ``<joint>.<quantity>`` for single runs, each of :attr:`Ensemble.scalar_names`
            (``continuous_contact``, which the file lacks, and ``settled`` as 1 or 0, NaN where
            the file's cell is empty; the window of each is its ``window`` in
            :attr:`Ensemble.statistics`: ``contact_fraction``, ``impacts_per_rotation`` and
            ``continuous_contact`` are of the recorded rotations), and
            ``<joint>.motion_mode``, or
            ``<joint>.<quantity>.n`` (members where it is defined), ``.mean``, ``.sd`` and its
            states (``.states`` 1 or 2, ``.low_n``, ``.low_mean``, ``.low_sd``, ``.high_n``,
            ``.high_mean``, ``.high_sd``, NaN with one state; all NaN where ``.n`` is 0) for
            ensembles; ``wall_time_s``;
            NaN in the cases that failed.
        errors: the message of each case that failed while running, else None.
    """

    def __init__(
        self,
        keys: Sequence[str],
        combos: Sequence[Tuple[Any, ...]],
        cases: Sequence[Dict[str, Any]],
        members: Optional[int],
    ) -> None:
        self.keys: List[str] = list(keys)
        self.members = members
        self.errors: List[Optional[str]] = [c["error"] for c in cases]
        names: List[str] = []
        for c in cases:
            for k in c:
                if k not in ("case", "error") and k not in names:
                    names.append(k)
        # the program's column order: members (ensembles), the recorded window, the joints'
        # columns, wall time
        order = {"members": 0, "record_rotations": 1, "record_interval_s": 2, "wall_time_s": 4}
        names.sort(key=lambda k: order.get(k, 3))
        columns: Dict[str, Any] = {"case": np.array([c["case"] for c in cases], dtype=np.int64)}
        for i, key in enumerate(self.keys):
            columns[key] = _column([combos[c["case"]][i] for c in cases])
        for name in names:
            columns[name] = _column([c.get(name, float("nan")) for c in cases])
        self.columns: Dict[str, Any] = columns

    def __len__(self) -> int:
        return len(self.errors)

    def __getitem__(self, column: str):
        return self.columns[column]

    def best(self, column: str) -> Dict[str, Any]:
        """The case (a dict of its swept values and ``column``) where the numeric ``column``
        is least, ignoring failed cases and NaN. For an ensemble's ``<joint>.<quantity>.mean``
        the dict also has that quantity's ``.states``, ``.low_n``, ``.low_mean``,
        ``.high_n`` and ``.high_mean`` in that case, as :attr:`Ensemble.statistics` has them
        (the counts ints, None with one state): a mean pooled over two states is no state's
        value. Raises KeyError for a column the sweep does not have, ValueError for one that
        is not numeric or has no value."""
        if column not in self.columns:
            raise KeyError(f"no column {column!r} in the sweep; its columns: {list(self.columns)}")
        values = self.columns[column]
        if not isinstance(values, np.ndarray):
            raise ValueError(f"column {column!r} is not numeric: no case is least in it")
        if np.all(np.isnan(values)):
            raise ValueError(f"no case has a value of {column!r}")
        i = int(np.nanargmin(values))
        out = {k: _scalar(self.columns[k][i]) for k in self.keys}
        out[column] = float(values[i])
        if column.endswith(".mean"):
            quantity = column[: -len("mean")]
            for state in ("states", "low_n", "low_mean", "high_n", "high_mean"):
                if quantity + state in self.columns:
                    x = float(self.columns[quantity + state][i])
                    count = state in ("states", "low_n", "high_n")
                    out[quantity + state] = None if np.isnan(x) else int(x) if count else x
        return out

    def to_pandas(self):
        """The sweep as a pandas DataFrame (one row per case, with an ``error`` column).
        Raises ImportError if pandas is not installed."""
        pd = _pandas("SweepResult.to_pandas()")
        frame = pd.DataFrame(self.columns)
        frame["error"] = self.errors
        return frame

    def __repr__(self) -> str:
        failed = sum(e is not None for e in self.errors)
        return f"SweepResult(keys={self.keys}, cases={len(self)}, failed={failed})"


def _column(values: List[Any]):
    """A numeric column as a float64 array, anything else as a list."""
    if all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) for v in values):
        return np.asarray(values, dtype=np.float64)
    return list(values)


def _scalar(v: Any) -> Any:
    """A numpy scalar as the Python number it holds."""
    return v.item() if isinstance(v, np.generic) else v
