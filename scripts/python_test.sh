#!/usr/bin/env bash
# The Python package's tests (python/tests, pytest): the extension built in the test profile
# (it reuses what `cargo test` built: under a minute, where a release wheel takes minutes) and loaded
# from a temporary copy of the package, against the server binary of the same build. Installs
# pytest, numpy, pandas and Dask with pip if they are missing; `pip install ./python` builds
# the release wheel a user installs (docs/python.md).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! python3 -c 'import numpy, pytest, pandas, distributed' 2>/dev/null; then
    python3 -m pip install --quiet "numpy>=1.24" "pytest>=8" "pandas>=2" "dask[distributed]>=2024.1"
fi
export PYO3_PYTHON="$(command -v python3)"
# The whole workspace with its tests, as `cargo test --workspace` builds it, so that features
# unify as they did there: only the extension itself is new (`-p nhlab-python` alone would
# rebuild the server and its HTTP stack with other features, minutes).
cargo build --quiet --profile test --workspace --lib --bins --tests
target="${CARGO_TARGET_DIR:-target}/debug"
package=$(mktemp -d)
trap 'rm -rf "$package"' EXIT
cp -r python/nhlab "$package/"
cp "$target/lib_nhlab.so" "$package/nhlab/_nhlab.abi3.so"
PYTHONPATH="$package" NHLAB_BINARY="$target/nhlab" python3 -m pytest -q -p no:cacheprovider python/tests "$@"
