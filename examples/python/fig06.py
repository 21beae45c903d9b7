"""Paper figure 6 from Python: mean wear depth of the standard slider-crank's bearing against
bearing angle after 10, 20, 30 and 40 crank rotations, over an ensemble, with the band that
holds 90 % of the members shaded (what `cargo run --release --bin fig06` draws).

    python examples/python/fig06.py                 # 32 members, about 5 s on 2 cores
    python examples/python/fig06.py --members 8     # quicker, a noisier band

Writes examples/python/out/fig06.png (or --out) and, with the default 32 members and seed 1,
compares the means with data/fig06.csv, written by the Rust program from the same ensemble.
Needs numpy and matplotlib.
"""

import argparse
import csv
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jointwear  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
JOINT = "rod-slider"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--members", type=int, default=32, help="ensemble members (default 32)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the initial offsets")
    parser.add_argument("--out", type=Path, default=ROOT / "examples/python/out/fig06.png")
    args = parser.parse_args()

    scene = jointwear.Scene.load(ROOT / "data/scenes/standard.toml")
    # the figure needs the profiles only: no time series
    scene.set("run.record_rotations", 0)
    clock = time.perf_counter()
    ens = scene.ensemble(members=args.members, seed=args.seed)
    print(f"{ens.members} members of {ens.rotations} rotations in {time.perf_counter() - clock:.1f} s")

    angles = ens.angles_deg[JOINT]
    snaps_um = ens.snapshots[JOINT] * 1e6  # (member, snapshot, sector), µm
    fig, ax = plt.subplots(figsize=(8, 4.8), dpi=120)
    means = {}
    for i, rotation in enumerate(ens.snapshot_rotations):
        members = snaps_um[:, i, :]
        mean = members.mean(axis=0)
        lo, hi = np.quantile(members, [0.05, 0.95], axis=0)
        means[int(rotation)] = mean
        (line,) = ax.plot(angles, mean, label=f"{rotation} rotations")
        ax.fill_between(angles, lo, hi, color=line.get_color(), alpha=0.25, linewidth=0)
        k = int(np.argmax(mean))
        print(f"after {rotation:2d} rotations: deepest mean wear {mean[k]:.4f} µm at {angles[k]:.1f} deg")
    ax.set(
        xlim=(0, 360),
        xlabel="bearing angle (deg)",
        ylabel="wear depth (µm)",
        title=f"Wear with crank rotation (0.02 mm, 2000 r/min), mean of {ens.members}, 5-95 % shaded",
    )
    ax.xaxis.set_major_locator(matplotlib.ticker.MultipleLocator(45))
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    print(f"wrote {args.out}")

    reference = ROOT / "data/fig06.csv"
    if (args.members, args.seed) == (32, 1) and reference.exists():
        with open(reference, newline="") as f:
            rows = list(csv.DictReader(f))
        worst = 0.0
        for rotation, mean in means.items():
            rust_um = np.array([float(r[f"rot{rotation}_mean_mm"]) for r in rows]) * 1e3
            worst = max(worst, float(np.max(np.abs(mean - rust_um) / rust_um.max())))
        print(f"largest difference from data/fig06.csv (the Rust program): {worst:.1e} of the peak")


if __name__ == "__main__":
    main()
