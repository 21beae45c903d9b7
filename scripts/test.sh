#!/usr/bin/env bash
# Every test, Rust and Python: `cargo test --release`, then the Python package built from this
# repository (pip, maturin) into a virtual environment under the target directory, and pytest
# on python/tests/ (which compares the bindings with the `jointwear` program built here).
#
# Needs the Rust toolchain and Python >= 3.9 with pip; PyPI and crates.io must be reachable.
# PYTHON picks the interpreter (default python3); CARGO_TARGET_DIR is honoured by both builds.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-$PWD/target}"
python="${PYTHON:-python3}"

cargo test --release
# the program the Python tests compare with (already built by the integration tests)
cargo build --release --bin jointwear

python_start=$(date +%s)
venv="$target/python-venv"
if [ ! -x "$venv/bin/python" ]; then
    echo "creating $venv"
    if ! "$python" -m venv "$venv"; then
        # Python without its venv module (Debian's python3 without python3-venv)
        rm -rf "$venv"
        "$python" -m pip install --quiet --target "$target/python-tools" virtualenv
        PYTHONPATH="$target/python-tools" "$python" -m virtualenv --quiet "$venv"
    fi
fi
install_start=$(date +%s)
# Rebuilds the extension from the working tree (release profile, feature `python`) and
# installs it with numpy, pytest and pandas (extra `test`) and the examples' matplotlib and
# scipy (extra `examples`), which python/tests/test_examples.py runs.
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check ".[test,examples]"
echo "python package built and installed in $(( $(date +%s) - install_start )) s"
JOINTWEAR_CLI="$target/release/jointwear" "$venv/bin/python" -m pytest python/tests -q
echo "python part (environment, build, tests): $(( $(date +%s) - python_start )) s"
