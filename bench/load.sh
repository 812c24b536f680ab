#!/usr/bin/env bash
# Load test of the release server with wrk (apt), on loopback, with bounded durations:
#
#  1. POST /simulate, the paper's knife-edge experiment ({"system":"knife_edge","preset":
#     "paper"}: five methods, 318 steps each, every integral): throughput and latency with as
#     many connections as simulation slots (default: the number of cores), so that no request
#     is refused; fails if any answer is not 200.
#  2. GET /health (one connection) while 4 long streams (the paper's five methods each, 10⁸
#     steps: 20 computing threads) keep every slot and core busy: latency.
#
#   bench/load.sh                 # 10 s per measurement
#   DURATION=30 bench/load.sh
#
# Targets on a 2-core machine: ≥ 300 knife-edge requests/s with p99 < 50 ms; /health p99
# < 50 ms under the streams.
set -euo pipefail
cd "$(dirname "$0")/.."
DURATION=${DURATION:-10}
SLOTS=${SLOTS:-$(nproc)}

command -v wrk >/dev/null || { apt-get update -qq && apt-get install -y -qq wrk; }
command -v curl >/dev/null || { apt-get update -qq && apt-get install -y -qq curl; }
cargo build --release --quiet -p nhlab-server
binary="${CARGO_TARGET_DIR:-target}/release/nhlab"

work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
    rm -rf "$work"
}
trap cleanup EXIT

# Starts the server with "$@"; sets $url.
start_server() {
    "$binary" --addr 127.0.0.1:0 "$@" 2>"$work/server.log" &
    pids+=($!)
    url=
    for _ in $(seq 100); do
        url=$(grep -o 'listening on http://[0-9.:]*' "$work/server.log" | sed 's/listening on //' || true)
        [[ -n $url ]] && return
        sleep 0.1
    done
    cat "$work/server.log" >&2
    echo "the server did not start" >&2
    exit 1
}

stop_server() {
    local pid=${pids[-1]}
    kill "$pid"
    wait "$pid" 2>/dev/null || true
    unset 'pids[-1]'
}

cat >"$work/knife_edge.lua" <<'LUA'
wrk.method = "POST"
wrk.body = '{"system":"knife_edge","preset":"paper"}'
wrk.headers["Content-Type"] = "application/json"
LUA

echo "== 1. POST /simulate knife_edge/paper, $SLOTS connections (= slots), ${DURATION} s" >&2
start_server --max-simulations "$SLOTS"
curl -sf "$url/simulate" --json '{"system":"knife_edge","preset":"paper"}' -o "$work/one.json"
echo "one answer: $(wc -c <"$work/one.json") bytes" >&2
threads=$((SLOTS < 2 ? SLOTS : 2))
wrk -t"$threads" -c"$SLOTS" -d"${DURATION}s" --latency -s "$work/knife_edge.lua" "$url/simulate" \
    | tee "$work/simulate.txt"
if grep -q "Non-2xx" "$work/simulate.txt"; then echo "some requests were refused" >&2; exit 1; fi
stop_server

echo "== 2. GET /health while 4 long streams compute, ${DURATION} s" >&2
start_server --max-simulations 4
long='{"system":"knife_edge","step":1e-6,"t_end":100}'
for _ in 1 2 3 4; do
    curl -sfN "$url/simulate" -H 'accept: text/event-stream' -d "$long" -o /dev/null &
    pids+=($!)
done
for _ in $(seq 100); do
    curl -sf "$url/health" | grep -q '"simulations":4' && break
    sleep 0.1
done
echo "before: $(curl -sf "$url/health")" >&2
wrk -t1 -c1 -d"${DURATION}s" --latency "$url/health" | tee "$work/health.txt"
after=$(curl -sf "$url/health")
echo "after:  $after" >&2
[[ $after == *'"simulations":4'* && $after == *'"active_runs":20'* ]] \
    || { echo "the streams were not all computing throughout" >&2; exit 1; }

summary() { # file label
    local rps p50 p99
    rps=$(awk '/Requests\/sec/ {print $2}' "$1")
    p50=$(awk '$1 == "50%" {print $2}' "$1")
    p99=$(awk '$1 == "99%" {print $2}' "$1")
    echo "$2: $rps req/s, p50 $p50, p99 $p99"
}
echo "== summary ($(nproc) cores)"
summary "$work/simulate.txt" "POST /simulate knife_edge/paper, $SLOTS connections"
summary "$work/health.txt" "GET /health, 1 connection, 4 long streams running"
