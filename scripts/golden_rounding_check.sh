#!/usr/bin/env bash
# Shows that the golden tests hold the model's statistics, not one trajectory: a change of
# rounding that leaves the physics alone (the order of the products of the hybrid elastic force,
# src/laws/contact.rs, which every contact evaluation of the scenes computes) moves a single
# run's wear, yet leaves the golden tests green without re-recording. The physics-change half
# (restitution 0.9 -> 0.8, mu_d 0.01 -> 0.03 turn them red) is the test
# `a_change_of_physics_breaks_them`.
#
# Usage: scripts/golden_rounding_check.sh   (a copy of the tree in a temporary folder; about
# 5 minutes on 2 cores, most of it the rebuild and the golden ensembles)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -C "$root" --exclude=./target --exclude=./out -cf - . | tar -C "$work" -xf -
file="$work/src/laws/contact.rs"
before='(3.0 \* delta_r + 2.0 \* delta) \* delta \* delta'
after='(3.0 * delta_r + 2.0 * delta) * (delta * delta)'
grep -q "$before" "$file" || { echo "the hybrid force's line was not found in $file: update this script"; exit 1; }
sed -i "s/$before/$after/" "$file"

peak() { # the most prominent wear region of one run of the standard scene
    (cd "$1" && cargo run --release --quiet --bin jointwear -- run data/scenes/standard.toml \
        --out "$work/out-$2" | grep -m1 'wear region')
}
echo "single run, as committed:        $(peak "$root" committed)"
echo "single run, products reordered:  $(peak "$work" reordered)"
echo "golden tests on statistics, products reordered, nothing re-recorded:"
(cd "$work" && cargo test --release --quiet --test golden recorded_statistics)
