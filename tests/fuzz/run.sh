#!/usr/bin/env bash
# Fuzzes the API with schemathesis (PyPI) from its own OpenAPI document (/openapi.json):
# bodies generated from the schemas (ids as enums, bounds as minimum/maximum) and their
# negations. Fails on any 5xx, any error that is not JSON, or any answer that contradicts the
# document (status, content type, schema). Bounded: EXAMPLES cases per operation and phase
# (default 1000), about two minutes once built.
#
#   tests/fuzz/run.sh            # builds the server (test profile), runs it on a free port
#   EXAMPLES=2000 SEED=7 tests/fuzz/run.sh
#
# The server runs with small step limits so that a generated request never takes long; the
# limits themselves are checked by the Rust tests. Schemathesis therefore warns that
# POST /work-precision "mostly rejected generated data": most generated scenes, halved
# `levels` times, exceed those limits (a 422 naming the field), which a schema cannot state.
set -euo pipefail
cd "$(dirname "$0")/../.."
EXAMPLES=${EXAMPLES:-1000}
SCHEMATHESIS_VERSION=4.32.5

if ! command -v schemathesis >/dev/null || [[ $(schemathesis --version) != *"$SCHEMATHESIS_VERSION"* ]]; then
    python3 -m pip install --quiet "schemathesis==$SCHEMATHESIS_VERSION"
fi

# The test profile (optimized, debug assertions on) as `cargo test --workspace` builds it: the
# whole workspace with its tests, so that features unify as they did there and nothing is
# rebuilt (`-p nhlab-server` alone would rebuild the server and its HTTP stack).
cargo build --quiet --profile test --workspace --lib --bins --tests
binary="${CARGO_TARGET_DIR:-target}/debug/nhlab"

work=$(mktemp -d)
server_pid=
cleanup() {
    if [[ ${status:-0} != 0 && -f $work/server.log ]]; then
        echo "--- server log (errors and panics) ---" >&2
        grep -E 'ERROR|panicked|status=5' "$work/server.log" | tail -50 >&2 || true
    fi
    if [[ -n $server_pid ]]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
    rm -rf "$work"
}
trap 'status=$?; cleanup' EXIT

# A body over the size limit gets 413, which schemathesis's negative-data check does not count
# as a rejection; its generated bodies reach a few hundred KB, so the limit is raised here.
"$binary" --addr 127.0.0.1:0 --max-simulations 8 --max-body-bytes 4194304 \
    --max-steps-json 20000 --max-steps-stream 20000 --max-points 2000 \
    --max-sweep-cells 64 --max-sweep-steps 200000 2>"$work/server.log" &
server_pid=$!
url=
for _ in $(seq 100); do
    url=$(grep -o 'listening on http://[0-9.:]*' "$work/server.log" | sed 's/listening on //' || true)
    [[ -n $url ]] && break
    sleep 0.1
done
[[ -n $url ]] || { cat "$work/server.log" >&2; echo "the server did not start" >&2; exit 1; }
echo "fuzzing $url with $EXAMPLES examples per operation" >&2

cd "$work"
# One worker: schemathesis's workers are threads, and on CPython 3.11 two threads inside
# `ast.parse` at once (Hypothesis describing its strategies) can raise "SystemError: AST
# constructor recursion depth mismatch", a flaky failure that is not the API's.
schemathesis run "$url/openapi.json" \
    --checks all \
    --exclude-checks positive_data_acceptance,ignored_auth,use_after_free,ensure_resource_availability,object_level_authorization \
    --max-examples "$EXAMPLES" \
    --workers 1 \
    --seed "${SEED:-6}" \
    --generation-database none \
    --request-timeout 30 \
    --no-color \
    --output-truncate true
# What the generated requests got, per route and status (the log's one line per request).
echo "answers by route and status:" >&2
grep -o 'uri=[^ ]*.*status=[0-9]*' "$work/server.log" | sed -E 's/uri=([^ }?]*).*status=([0-9]+).*/\1 \2/' \
    | sort | uniq -c | sort -k2,2 -k3,3 >&2 || true
echo "fuzz: no 5xx, every error JSON, every answer as documented" >&2
