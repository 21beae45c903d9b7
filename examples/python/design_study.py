"""A small design study from Python: which radial clearance and crank speed of the standard
slider-crank give the shallowest deepest wear (max_wear_depth_m)?

Runs an ensemble sweep over a grid of clearance and speed (each case the mean deepest wear of
a few members after a few rotations: single runs are chaotic), takes the best grid point and,
where scipy is installed, refines it: a smooth surrogate of the grid (a bicubic spline in log
clearance and speed) is minimised within the grid's bounds, and the optimum it proposes is
simulated to confirm it. Without scipy the grid's best point is the answer.

    python examples/python/design_study.py            # 5 x 4 cases x 4 members x 10 rotations
    python examples/python/design_study.py --quick    # 3 x 3 cases x 2 members x 4 rotations

Writes examples/python/out/design_study.png (or --out). Needs numpy and matplotlib; uses scipy
if installed.
"""

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jointwear  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
JOINT = "rod-slider"
PEAK = f"{JOINT}.max_wear_depth_m.mean"


def study_scene(rotations: int) -> jointwear.Scene:
    """The standard scene, shortened: `rotations` of wear, no time series."""
    scene = jointwear.Scene.load(ROOT / "data/scenes/standard.toml")
    scene.set("run.rotations", rotations)
    scene.set("run.wear_snapshots", [])
    scene.set("run.record_rotations", 1)  # the motion columns need the last rotation
    return scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a 3 x 3 grid, 2 members, 4 rotations")
    parser.add_argument("--no-scipy", action="store_true", help="grid only, even with scipy")
    parser.add_argument("--out", type=Path, default=ROOT / "examples/python/out/design_study.png")
    args = parser.parse_args()
    if args.quick:
        clearances, speeds, members, rotations = [0.02, 0.05, 0.1], [600, 1200, 2000], 2, 4
    else:
        clearances = [0.02, 0.035, 0.05, 0.1, 0.2]
        speeds = [600, 1000, 1500, 2000]
        members, rotations = 4, 10

    scene = study_scene(rotations)
    # the standard crank turns clockwise: negative speeds in the scene
    grid = {"clearance.0.clearance_mm": clearances, "driver.speed_rpm": [-s for s in speeds]}
    clock = time.perf_counter()
    sweep = scene.sweep(grid, members=members, seed=1)
    print(f"{len(sweep)} cases x {members} members x {rotations} rotations in {time.perf_counter() - clock:.1f} s")
    for e in sweep.errors:
        if e is not None:
            print(f"failed case: {e}")
    peak_um = sweep[PEAK].reshape(len(clearances), len(speeds)) * 1e6

    best = sweep.best(PEAK)
    best_c, best_s = best["clearance.0.clearance_mm"], -best["driver.speed_rpm"]
    print(
        f"best grid point: clearance {best_c} mm, {best_s:.0f} r/min: deepest wear, mean of "
        f"{members} members after {rotations} rotations, {best[PEAK] * 1e6:.4f} µm"
    )
    states = PEAK[: -len("mean")]
    if best[states + "states"] == 2:
        # a mean pooled over two states is neither's value
        print(
            f"  its members fall into two states: {best[states + 'low_n']:.0f} at "
            f"{best[states + 'low_mean'] * 1e6:.4f} µm, {best[states + 'high_n']:.0f} at "
            f"{best[states + 'high_mean'] * 1e6:.4f} µm"
        )

    refined = None
    if not args.no_scipy:
        try:
            from scipy.interpolate import RectBivariateSpline
            from scipy.optimize import minimize
        except ImportError:
            print("scipy is not installed: the grid's best point is the answer")
        else:
            refined = refine(scene, clearances, speeds, peak_um, best_c, best_s, members,
                             RectBivariateSpline, minimize)

    if refined is not None and refined[2] < best[PEAK] * 1e6:
        print(f"answer: clearance {refined[0]:.4f} mm at {refined[1]:.0f} r/min (scipy)")
    else:
        print(f"answer: clearance {best_c} mm at {best_s:.0f} r/min (grid)")

    fig, ax = plt.subplots(figsize=(7, 5.4), dpi=120)
    mesh = ax.pcolormesh(speeds, clearances, peak_um, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label=f"mean deepest wear after {rotations} rotations (µm)")
    for i, c in enumerate(clearances):
        for j, s in enumerate(speeds):
            ax.annotate(f"{peak_um[i, j]:.3f}", (s, c), ha="center", va="center", fontsize=7, color="w")
    ax.plot(best_s, best_c, "o", mfc="none", mec="red", ms=16, mew=2, label="best grid point")
    if refined is not None:
        ax.plot(refined[1], refined[0], "x", color="red", ms=12, mew=2, label="scipy optimum (simulated)")
    ax.set(
        yscale="log",
        xlabel="crank speed (r/min)",
        ylabel="radial clearance (mm)",
        title=f"Standard slider-crank: deepest wear, mean of {members} members",
    )
    ax.set_yticks(clearances, [f"{c:g}" for c in clearances])
    ax.minorticks_off()
    ax.set_xticks(speeds)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, fontsize=8, frameon=False)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    print(f"wrote {args.out}")


def refine(scene, clearances, speeds, peak_um, best_c, best_s, members, spline, minimize):
    """Minimises a spline surrogate of the grid (log clearance, speed) from the best grid
    point within the grid's bounds, and simulates the optimum it proposes."""
    x, y = np.log(clearances), np.asarray(speeds, dtype=float)
    surrogate = spline(x, y, peak_um, kx=min(3, len(x) - 1), ky=min(3, len(y) - 1))
    scale = np.array([x[-1] - x[0], y[-1] - y[0]])  # the optimiser works on [0, 1]²
    low = np.array([x[0], y[0]])

    def objective(u):
        p = low + u * scale
        return float(surrogate(p[0], p[1], grid=False))

    start = (np.array([np.log(best_c), best_s]) - low) / scale
    result = minimize(objective, start, method="L-BFGS-B", bounds=[(0, 1), (0, 1)])
    log_c, speed = low + result.x * scale
    clearance = float(np.exp(log_c))
    check = scene.copy()
    check.set("clearance.0.clearance_mm", clearance).set("driver.speed_rpm", -float(speed))
    ens = check.ensemble(members=members, seed=1)
    simulated = ens.statistics[JOINT]["max_wear_depth_m"]["mean"] * 1e6
    print(
        f"scipy optimum of the surrogate: clearance {clearance:.4f} mm, {speed:.0f} r/min: "
        f"predicted {result.fun:.4f} µm, simulated {simulated:.4f} µm "
        f"(best grid point {surrogate(np.log(best_c), best_s, grid=False):.4f} µm on the surrogate)"
    )
    return clearance, speed, simulated


if __name__ == "__main__":
    main()
