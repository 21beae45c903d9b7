"""jointwear: wear prediction in planar mechanisms with clearance revolute joints.

Python bindings of the Rust crate ``jointwear``: load a scene file (or build a scene from a
dict with the keys of a scene file), change values by dotted keys as the ``jointwear``
program's ``--set`` does, and run it once, as an ensemble or as a sweep. Results are numpy
arrays in SI units (m, N, s, rad; angles of wear profiles in degrees), with ``to_pandas()``
where pandas is installed.

>>> import jointwear
>>> scene = jointwear.Scene.load("data/scenes/standard.toml")
>>> scene.set("run.rotations", 2).set("run.wear_snapshots", [])
>>> run = scene.run()                       # the GIL is released while it runs
>>> run.wear["rod-slider"].max()            # deepest wear of the final profile (m)

``run.save(dir)`` and ``ensemble.save(dir)`` write the folder ``jointwear run --out dir`` writes;
``scene.ensemble(..., executor=pool)`` and ``scene.sweep(..., executor=pool)`` spread the members
or cases over any ``concurrent.futures.Executor`` with bit for bit the same results.

Bad input raises :class:`SceneError` (a ``ValueError``) and a failure while running
:class:`SimulationError` (a ``RuntimeError``), with the message the ``jointwear`` program
prints for the same input.
"""

from ._native import SceneError, SimulationError, __version__
from ._results import Ensemble, Run, SweepResult
from ._scene import Scene

__all__ = [
    "Scene",
    "Run",
    "Ensemble",
    "SweepResult",
    "SceneError",
    "SimulationError",
    "__version__",
]
