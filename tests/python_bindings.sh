#!/usr/bin/env bash
# The Python bindings as a user gets them: a fresh virtual environment,
# `pip install ./python` (the README's command: maturin builds the module
# from this checkout), then pytest over python/tests, which also runs
# examples/python/paper_drive.py and checks the type stubs with mypy's
# stubtest. Lints of the bindings' Rust first (their formatting is in the
# workspace's `cargo fmt --check`).
#
#   bash tests/python_bindings.sh
#
# Skips, saying so, only where there is no Python at all; network access
# for `pip` (maturin, numpy, pandas, matplotlib, pytest, jsonschema, mypy).
set -euo pipefail
cd "$(dirname "$0")/.."
python=$(command -v python3 || command -v python || true)
if [ -z "$python" ]; then
  echo "python bindings: SKIPPED: no python3 or python on PATH, so the bindings cannot be built or tested"
  exit 0
fi
cargo clippy -p chaindrive-python --release -- -D warnings
venv=target/python-ci-venv
rm -rf "$venv"
"$python" -m venv "$venv"
"$venv/bin/pip" install --quiet --upgrade pip
"$venv/bin/pip" install --quiet ./python
"$venv/bin/python" -c 'import chaindrive; print("python bindings: chaindrive", chaindrive.__version__, "imported from", chaindrive.__file__)'
"$venv/bin/pip" install --quiet pytest jsonschema pandas matplotlib mypy
# From outside the source tree: the installed package is the one tested.
(cd target && "../$venv/bin/python" -m pytest -q -p no:cacheprovider ../python/tests)
