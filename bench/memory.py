#!/usr/bin/env python3
"""Memory counted as it is: the answer budget's estimate of the largest answers against the
memory the server really takes for them.

Each case starts the release server afresh (default flags unless given after `--`), waits
for it to be idle, reads its RSS (VmRSS), resets its peak (VmHWM, through
/proc/PID/clear_refs) and sends the case. The budget's count is GET /health's
`answer_bytes_peak` once it is done: the most bytes the answers in flight reserved at once
(a server without that field is polled every 10 ms for `answer_bytes` instead). Peak RSS
above the idle server's over that count is the ratio reported; the target is ≤ 1.5.

The cases are the largest answers the default limits allow (16 methods, 10⁵ points, 64 MiB
per answer, 10⁴ cells per sweep):
  - simulate-long: one method, 5 series × 10⁵ points, as JSON;
  - simulate-wide: 16 methods × 5 series × 6,500 points, as JSON;
  - scorecard: one scene, 16 methods × 5 series × 17,000 points (what a scorecard keeps
    for its verdicts is one scene's runs at a time);
  - scorecard-16: 16 scenes × 16 methods × 5 series × 17,000 points (a server that
    counts the scenes' series summed refuses it: 65 points is its largest);
  - sweep-json and sweep-csv: 10⁴ cells × 5 methods (50,000 rows) of the rotating CVT;
  - five-unread: five JSON sweeps of 8,000 cells sent one after another and never read:
    each answer stays in the server, written to a client that does not read it; the
    budget's count is what /health says they hold together once all five are done
    (`--write-timeout 600`: the first answer waits for the fifth however slow the machine).

The answers are read as they come (a slow reader would only change when the memory is
given back, not how much). Prints a Markdown table: estimate (MiB), peak RSS above idle
(MiB), their ratio, and the answer's size.

  cargo build --release -p nhlab-server
  python3 bench/memory.py [--skip-build] [--cases sweep-json,five-unread] [-- SERVER FLAGS]
  python3 bench/memory.py --binary OLD_BINARY     # another build, e.g. before a change
"""

import argparse
import json
import socket
import sys
import threading
import time

from nhlab_bench import Server, build, hwm_kib, log, reset_hwm, rss_kib

MIB = 1024 * 1024
CVT = {"system": "cvt_pendulum", "preset": "rotating"}
WIDE_METHODS = ["leapfrog", "dla", "dla01", "rk4"] * 4


def sweep(cells_eps, cells_q):
    """The rotating CVT over ε × q[0], the paper's five methods, 20 steps of 0.01."""
    return {**CVT, "t_end": 0.2, "step": 0.01, "points": 1000,
            "axes": [{"path": "params.epsilon", "linspace": [0.1, 0.5, cells_eps]},
                     {"path": "q[0]", "linspace": [0.5, 1.5, cells_q]}]}


CASES = {
    "simulate-long": ("/simulate", "application/json",
                      {**CVT, "t_end": 2000, "step": 0.01, "points": 100000,
                       "methods": ["leapfrog"]}),
    "simulate-wide": ("/simulate", "application/json",
                      {**CVT, "t_end": 100, "step": 0.01, "points": 6500,
                       "methods": WIDE_METHODS}),
    "scorecard": ("/scorecard", "application/json",
                  {"scenes": [{**CVT, "t_end": 200, "step": 0.01}], "methods": WIDE_METHODS,
                   "points": 17000}),
    "scorecard-16": ("/scorecard", "application/json",
                     {"scenes": [{**CVT, "t_end": 200, "step": 0.01}] * 16,
                      "methods": WIDE_METHODS, "points": 17000}),
    "sweep-json": ("/sweep", "application/json", sweep(100, 100)),
    "sweep-csv": ("/sweep", "text/csv", sweep(100, 100)),
}
UNREAD = ("/sweep", "application/json", sweep(80, 100))


class Health(threading.Thread):
    """Polls /health every 10 ms: the largest `answer_bytes` seen, and the last answer."""

    def __init__(self, server):
        super().__init__(daemon=True)
        self.server, self.peak, self.last = server, 0, None
        self.done = threading.Event()

    def run(self):
        while not self.done.is_set():
            try:
                self.last = self.server.get("/health")
                self.peak = max(self.peak, self.last["answer_bytes"])
            except (OSError, ValueError):
                pass
            time.sleep(0.01)

    def stop(self):
        self.done.set()
        self.join()
        return self.peak


def send(server, path, accept, body):
    """Sends a request on a raw socket (nothing read yet)."""
    data = json.dumps(body).encode()
    sock = socket.create_connection((server.host, server.port))
    sock.sendall(
        f"POST {path} HTTP/1.1\r\nHost: memory\r\nAccept: {accept}\r\n"
        f"Content-Type: application/json\r\nContent-Length: {len(data)}\r\n"
        f"Connection: close\r\n\r\n".encode() + data)
    return sock


def read_all(sock):
    """The response's status and its length in bytes (or its error), read to the end."""
    chunks = []
    while chunk := sock.recv(1 << 20):
        chunks.append(chunk)
    sock.close()
    raw = b"".join(chunks)
    status = int(raw.split(b" ", 2)[1]) if raw else 0
    if status != 200:
        return status, raw.partition(b"\r\n\r\n")[2][:300].decode(errors="replace")
    return status, len(raw)


def idle(server):
    """Waits for the server to be idle (no slot, no budget), then its RSS in bytes."""
    for _ in range(500):
        h = server.get("/health")
        if h["simulations"] == 0 and h["active_runs"] == 0 and h["answer_bytes"] == 0:
            break
        time.sleep(0.02)
    time.sleep(0.2)
    return rss_kib(server.pid) * 1024


def one(binary, flags, name):
    path, accept, body = CASES[name]
    server = Server(binary, flags)
    try:
        base = idle(server)
        if not reset_hwm(server.pid):
            log("cannot reset VmHWM: the peak is the process's since it started")
        health = Health(server)
        health.start()
        t0 = time.perf_counter()
        status, size = read_all(send(server, path, accept, body))
        wall = time.perf_counter() - t0
        polled = health.stop()
        estimate = server.get("/health").get("answer_bytes_peak", polled)
        peak = hwm_kib(server.pid) * 1024 - base
    finally:
        server.stop()
    if status != 200:
        log(f"{name}: answered {status}: {size}")
        return {"case": name, "refused": status}
    return {"case": name, "estimate": estimate, "peak": peak, "answer": size, "wall": wall,
            "idle": base}


def five_unread(binary, flags):
    path, accept, body = UNREAD
    # A write timeout long enough that the first answer waits for the fifth on any machine.
    server = Server(binary, ["--write-timeout", "600", *flags])
    socks = []
    try:
        base = idle(server)
        reset_hwm(server.pid)
        t0 = time.perf_counter()
        for _ in range(5):
            socks.append(send(server, path, accept, body))
            # Wait for its answer to be computed (its slot free, its bytes still held).
            time.sleep(0.2)
            while True:
                h = server.get("/health")
                if h["simulations"] == 0 and h["active_runs"] == 0:
                    break
                time.sleep(0.05)
        time.sleep(0.5)
        estimate = server.get("/health")["answer_bytes"]
        wall = time.perf_counter() - t0
        rss = rss_kib(server.pid) * 1024 - base
        peak = hwm_kib(server.pid) * 1024 - base
        answers = [read_all(s) for s in socks]
        if any(status != 200 for status, _ in answers):
            sys.exit(f"five-unread: {answers}")
        size = sum(n for _, n in answers)
    finally:
        for s in socks:
            s.close()
        server.stop()
    log(f"five-unread: RSS while held {rss / MIB:.0f} MiB above idle")
    return {"case": "five-unread", "estimate": estimate, "peak": peak, "answer": size,
            "wall": wall, "idle": base, "held": rss}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--skip-build", action="store_true")
    p.add_argument("--binary", help="measure this server binary instead (no build)")
    p.add_argument("--cases", default=",".join([*CASES, "five-unread"]))
    p.add_argument("server_args", nargs="*")
    args = p.parse_args()
    binary = args.binary or build(args.skip_build)
    rows = []
    for name in args.cases.split(","):
        row = five_unread(binary, args.server_args) if name == "five-unread" else \
            one(binary, args.server_args, name)
        log(json.dumps(row))
        rows.append(row)
    print("| case | estimate MiB | peak RSS − idle MiB | ratio | answer MiB | idle MiB | wall s |")
    print("|---|---|---|---|---|---|---|")
    worst = 0.0
    for r in rows:
        if "refused" in r:
            print(f"| {r['case']} | refused ({r['refused']}) | | | | | |")
            continue
        ratio = r["peak"] / r["estimate"] if r["estimate"] else float("inf")
        worst = max(worst, ratio)
        print(f"| {r['case']} | {r['estimate'] / MIB:.1f} | {r['peak'] / MIB:.1f} | "
              f"{ratio:.2f} | {r['answer'] / MIB:.1f} | {r['idle'] / MIB:.1f} | "
              f"{r['wall']:.1f} |")
    print(f"\nworst ratio {worst:.2f} (target ≤ 1.5)")
    sys.exit(0 if worst <= 1.5 else 1)


if __name__ == "__main__":
    main()
