#!/usr/bin/env bash
# The Python package's tests (python/tests, docs/python.md): installs maturin, numpy,
# pytest and Mitsuba 3.9.1 with pip if missing, builds and installs the package from ./python
# (`pip install ./python`, in the same target folder as `cargo test`, whose compiled
# dependencies it shares where their features match), and runs pytest. The tests
# compare with the CLI's images, so the CLI must be built (`cargo test` or
# `cargo build` does that).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

py=${PYTHON:-python3}
need=()
"$py" -c 'import numpy' 2>/dev/null || need+=(numpy)
"$py" -c 'import pytest' 2>/dev/null || need+=(pytest)
# Mitsuba 3.9.1, the reference the mesh API's images are compared with (test_mesh.py).
"$py" -c 'import mitsuba' 2>/dev/null || need+=("mitsuba==3.9.1")
"$py" -m maturin --version >/dev/null 2>&1 || command -v maturin >/dev/null 2>&1 || need+=("maturin>=1.4,<2")
if [ ${#need[@]} -gt 0 ]; then
    echo "test_python.sh: pip install ${need[*]}" >&2
    "$py" -m pip install --quiet "${need[@]}"
fi

export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$PWD/target}
echo "== pip install ./python"
"$py" -m pip install --quiet --no-build-isolation --force-reinstall --no-deps ./python
echo "== pytest python/tests"
WAVETRACE_BIN=${WAVETRACE_BIN:-$CARGO_TARGET_DIR/debug/wavetrace} \
    "$py" -m pytest -q python/tests "$@"
