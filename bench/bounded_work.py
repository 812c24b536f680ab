#!/usr/bin/env python3
"""Work bounded in time on the release server, with a heavy system given as formulas (a smooth
U of ~1,800 characters; DLA∘p8s15 on it costs milliseconds per step):

  1. priced before admission: 16 such runs at the JSON step limit are refused (422) with
     their estimate, in well under a second;
  2. cancelled by time: a client that leaves a running heavy run (a JSON request, then a
     stream) — the run stops within 100 ms, measured from the moment the client closes
     its socket to /health's `active_runs` back at 0 (polled every millisecond);
  3. the wall-clock cap: with --max-run-seconds 1, a heavy run ends as `failed`, "time
     limit", about a second in.

Prints each number and exits non-zero if a target is missed. With --baseline, runs only
step 2 against a server that may lack the flags (an older build), to measure it before.

  cargo build --release -p nhlab-server && python3 bench/bounded_work.py [--skip-build]
"""

import argparse
import json
import socket
import sys
import time

from nhlab_bench import Server, build, log, post_json


def heavy_u(chars):
    """A U like tests/tests/bounded_work.rs's: a bowl with bumps, of about `chars` characters."""
    u = "0.5*(x^2 + y^2)"
    k = 0
    while len(u) < chars:
        a, b, c = 0.001 * (1 + k % 7), 1 + k % 5, 0.1 * (k % 9)
        u += [
            f" + {a:g}*cos({b}*x - {c:g}*y)",
            f" + {a:g}*x^2*y^2/(1 + {b}*x^2 + y^2)",
            f" + {a:g}*exp(-{b}*(x - {c:g})^2 - y^2)",
        ][k % 3]
        k += 1
    return u


def heavy(methods, t_end):
    return {
        "system": {"name": "heavy bowl", "passenger": ["x", "y"], "driver": "theta",
                   "parameters": {"eps": 0.1}, "passenger_potential": heavy_u(1800),
                   "driver_potential": "0",
                   "constraints": [["-sin(theta)", "cos(theta) - eps"]]},
        "q": [0.3, 0.2, 1.0], "v": [0, 0, 1], "step": 0.01, "t_end": t_end,
        "methods": methods, "points": 10,
    }


DLA_P8S15 = {"id": "dla", "composition": "p8s15"}


def active_runs(server):
    return server.get("/health")["active_runs"]


def departed(server, stream):
    """Starts a heavy run, leaves after 0.5 s of it; seconds until it stopped."""
    body = json.dumps(heavy([DLA_P8S15], 1000.0)).encode()
    accept = "text/event-stream" if stream else "application/json"
    s = socket.create_connection((server.host, server.port))
    s.sendall(
        b"POST /simulate HTTP/1.1\r\nHost: bench\r\nContent-Type: application/json\r\n"
        + f"Accept: {accept}\r\nContent-Length: {len(body)}\r\n\r\n".encode()
        + body
    )
    start = time.monotonic()
    while active_runs(server) == 0:
        if time.monotonic() - start > 30:
            sys.exit("the heavy run never started")
        time.sleep(0.005)
    time.sleep(0.5)
    if active_runs(server) == 0:
        sys.exit("the heavy run ended on its own within 0.5 s")
    s.close()
    left = time.monotonic()
    while active_runs(server) > 0:
        if time.monotonic() - left > 120:
            return float("inf")
        time.sleep(0.001)
    return time.monotonic() - left


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--skip-build", action="store_true")
    parser.add_argument("--binary", help="a server binary to use instead of the release build")
    parser.add_argument("--baseline", action="store_true",
                        help="only the departed-client timings, no new flags")
    args = parser.parse_args()
    binary = args.binary or build(skip=args.skip_build)
    missed = []
    if args.baseline:
        server = Server(binary)
        for stream in (False, True):
            took = departed(server, stream)
            print(f"{'stream' if stream else 'JSON'} client left: the run stopped after "
                  f"{took * 1e3:.0f} ms")
        server.stop()
        return
    server = Server(binary, ["--max-request-seconds", "300"])
    status, answer, wall = post_json(server, heavy([DLA_P8S15] * 16, 13_300.0))
    print(f"16 heavy p8s15 runs: {status} in {wall * 1e3:.0f} ms: {answer.get('error')}")
    if status != 422 or "max_request_seconds" not in answer.get("error", ""):
        missed.append(f"16 heavy runs got {status}")
    if wall > 2:
        missed.append(f"refused after {wall:.1f} s")
    server.stop()
    # Admitted whatever the estimate: what is measured is how soon the runs stop.
    server = Server(binary, ["--max-request-seconds", "1e7"])
    for stream in (False, True):
        took = departed(server, stream)
        kind = "stream" if stream else "JSON"
        print(f"{kind} client left: the heavy run stopped after {took * 1e3:.1f} ms")
        if not took < 0.1:
            missed.append(f"{kind}: stopped after {took * 1e3:.0f} ms")
    server.stop()
    server = Server(binary, ["--max-run-seconds", "1", "--max-request-seconds", "1e7"])
    status, answer, wall = post_json(server, heavy([DLA_P8S15], 1000.0))
    run = answer.get("runs", [{}])[0]
    print(f"past --max-run-seconds 1: {status} after {wall:.2f} s, {run.get('status')}: "
          f"{run.get('error')}")
    if run.get("status") != "failed" or "time limit" not in (run.get("error") or ""):
        missed.append("the capped run did not fail with 'time limit'")
    if not wall < 1.5:
        missed.append(f"the capped run answered after {wall:.2f} s")
    server.stop()
    for m in missed:
        log("MISSED:", m)
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
