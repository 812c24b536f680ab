#!/usr/bin/env bash
# Where a stream's server time goes: perf samples the release server (loopback, ephemeral
# port) while curl reads N streams of the paper's rotating-perturbed CVT preset (five methods,
# 30,000 steps, every integral, 1000 points: ~1.3 MB of events), then sorts the samples into
# compute (the integrators, libm, the run loop) and everything else (serialization, SSE framing,
# verdicts, allocation, kernel), and prints the top symbols of "everything else".
#
#   bench/profile_stream.sh              # 60 streams
#   N=200 BINARY=/path/to/nhlab bench/profile_stream.sh
#   MODE=figure_set N=20 bench/profile_stream.sh   # instead: N times the paper's six
#                                                  # experiments as JSON (POST /simulate)
#   KEEP=/tmp/perf.data bench/profile_stream.sh    # also keep the samples for perf report
#
# Needs perf (apt: linux-perf) and kernel.perf_event_paranoid ≤ 2 (or root).
set -euo pipefail
cd "$(dirname "$0")/.."
N=${N:-60}
MODE=${MODE:-stream}
if [[ -z ${BINARY:-} ]]; then
    cargo build --release --quiet -p nhlab-server
    BINARY="${CARGO_TARGET_DIR:-target}/release/nhlab"
fi
command -v perf >/dev/null || { echo "perf is missing (apt-get install linux-perf)" >&2; exit 1; }

work=$(mktemp -d)
server=
cleanup() {
    [[ -n $server ]] && kill "$server" 2>/dev/null && wait "$server" 2>/dev/null
    rm -rf "$work"
}
trap cleanup EXIT

"$BINARY" --addr 127.0.0.1:0 2>"$work/server.log" &
server=$!
url=
for _ in $(seq 100); do
    url=$(grep -o 'listening on http://[0-9.:]*' "$work/server.log" | sed 's/listening on //' || true)
    [[ -n $url ]] && break
    sleep 0.1
done
[[ -n $url ]] || { cat "$work/server.log" >&2; exit 1; }

body='{"system":"cvt_pendulum","preset":"rotating-perturbed"}'
one() {
    curl -sSf -N -o /dev/null -H 'accept: text/event-stream' -H 'content-type: application/json' \
        --data-binary "$body" "$url/simulate"
}
if [[ $MODE == figure_set ]]; then
    one() {
        for scene in knife_edge/paper knife_edge/paper-perturbed cvt_pendulum/oscillating \
            cvt_pendulum/rotating cvt_pendulum/oscillating-perturbed \
            cvt_pendulum/rotating-perturbed; do
            curl -sSf -o /dev/null -H 'content-type: application/json' \
                --data-binary "{\"system\":\"${scene%/*}\",\"preset\":\"${scene#*/}\"}" \
                "$url/simulate"
        done
    }
fi
one # warm-up
perf record -q -F 1999 -g -p "$server" -o "$work/perf.data" 2>"$work/perf.log" &
perf=$!
sleep 0.5
for _ in $(seq "$N"); do one; done
kill -INT "$perf"
wait "$perf" || true

[[ -n ${KEEP:-} ]] && cp "$work/perf.data" "$KEEP"
perf report -i "$work/perf.data" --no-children --sort symbol --stdio -g none 2>/dev/null \
    | python3 -c '
import re, sys
compute = re.compile(r"sincos|__sin_|__cos_|::step\b|call_once|floor|latitude|simulate::run|Method::run")
total, other = 0.0, []
for line in sys.stdin:
    m = re.match(r"\s+([0-9.]+)%\s+\[.\]\s+(.*\S)", line)
    if not m:
        continue
    p, name = float(m.group(1)), m.group(2)
    total += p
    if not compute.search(name):
        other.append((p, name))
rest = sum(p for p, _ in other)
print(f"samples: compute {total - rest:.1f} %, everything else {rest:.1f} % "
      f"(= {rest / max(1e-9, total - rest):.0%} of compute)")
for p, name in sorted(other, reverse=True)[:15]:
    print(f"  {p:5.2f} %  {name[:100]}")
'
