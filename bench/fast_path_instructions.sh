#!/usr/bin/env bash
# Instructions per step of every method with a fast path, on its fast and its general path,
# on every system (first preset): callgrind counts instructions, which do not move with the
# machine's load or the binary's layout as ns/step do (docs/performance.md, "How to measure"), so
# the fast/general ratio (a fast path is kept only where it is at least 2× its general path) can be
# read without noise. Instructions are not time: where a path waits on a long dependency chain its
# time ratio is below its instruction ratio.
#
#   bench/fast_path_instructions.sh            # needs valgrind (apt: valgrind)
#   STEPS=20000 bench/fast_path_instructions.sh
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is missing (apt-get install valgrind)" >&2; exit 1; }
cargo build --release --quiet -p nhlab-core --example step_loop
bin="${CARGO_TARGET_DIR:-target}/release/examples/step_loop"
steps=${STEPS:-10000}
count() { # system method path steps -> instructions, or nothing if the run failed
    local out
    # A run valgrind cannot finish (e.g. an instruction it does not decode: DD's exact end on
    # the 4×2 systems, with FMA) has no count.
    out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$@" 2>&1) || return 0
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p' <<<"$out"
}
per_step() { # system method path -> instructions per step, or n/a
    local a b
    a=$(count "$1" "$2" "$3" "$steps")
    b=$(count "$1" "$2" "$3" $((2 * steps)))
    if [[ -n $a && -n $b ]]; then echo $(((b - a) / steps)); else echo n/a; fi
}
echo "| system | method | fast path | general path | general / fast |"
echo "|---|---|---|---|---|"
for system in knife_edge cvt_pendulum cvt particle rolling_disk mobile_robot; do
    "$bin" list | while read -r index label has_general; do
        [[ $has_general == true ]] || continue
        fast=$(per_step "$system" "$index" fast)
        general=$(per_step "$system" "$index" general)
        ratio=n/a
        [[ $fast == n/a || $general == n/a ]] ||
            ratio=$(awk -v f="$fast" -v g="$general" 'BEGIN { printf "%.2f", g / f }')
        echo "| $system | ${label//_/ } | $fast | $general | $ratio |"
    done
done
