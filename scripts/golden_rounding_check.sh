#!/usr/bin/env bash
# Shows that the golden tests hold the model's statistics, not one trajectory: a change of
# rounding that leaves the physics alone (the summation order of the Baumgarte terms of every
# constraint row in the right-hand side, src/mechanism/ `accelerations`) moves a single run's
# wear peak, yet leaves the golden tests green without re-recording. The physics-change half (restitution 0.9 -> 0.8,
# mu_d 0.01 -> 0.03 turn them red) is the test `a_change_of_physics_breaks_them`.
#
# Usage: scripts/golden_rounding_check.sh   (a copy of the tree in a temporary folder; about
# 5 minutes on 2 cores, most of it the rebuild)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -C "$root" --exclude=./target --exclude=./out -cf - . | tar -C "$work" -xf -
before='\*b = g - 2.0 \* alpha \* row.dot(v) - beta \* beta \* \*b;'
after='*b = g - (beta * beta * *b + 2.0 * alpha * row.dot(v));'
grep -q "$before" "$work/src/mechanism/" || { echo "the Baumgarte line was not found: update this script"; exit 1; }
sed -i "s/$before/$after/" "$work/src/mechanism/"

peak() { # the deepest wear peak of one run of the standard scene
    (cd "$1" && cargo run --release --quiet --bin jointwear -- run data/scenes/standard.toml \
        --out "$work/out-$2" | grep -m1 'wear peak')
}
echo "single run, as committed:        $(peak "$root" committed)"
echo "single run, summation reordered: $(peak "$work" reordered)"
echo "golden tests on statistics, summation reordered, nothing re-recorded:"
(cd "$work" && cargo test --release --quiet --test golden recorded_statistics)
