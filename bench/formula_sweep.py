#!/usr/bin/env python3
"""Formula sweeps against the service: compiled once, checked in seconds, never locking others out.

Starts the given server binary on a free loopback port (extra arguments are passed to it) and
reproduces the hostile cases of sweeps over a parameter of a large system given as formulas
(a ~1,950-character U reading `k`, one step per run):
  1. a 10⁴-cell sweep: its time to answer and the server's peak RSS (VmHWM) after it;
  2. the same over the step limit: the time to its 422;
  3. two 2,000-cell sweeps at once while 32 small /simulate requests are sent: how many of
     those got 503.
Exits non-zero if a target is missed: (1) answered within 30 s, peak RSS less than 100 MiB
above the idle server's and the answer's own size; (2) within 2 s; (3) no small request
refused with 503 "busy checking" (503 "all slots taken" while the sweeps run is by design).

  cargo build --release -p nhlab-server
  python3 bench/formula_sweep.py target/release/nhlab [-- --max-simulations 2 ...]
"""

import argparse
import concurrent.futures
import json
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def large_system():
    terms, i = [], 0
    while len("+".join(terms)) < 1900:
        terms.append(f"0.{i % 9 + 1}*cos(x1*{i % 7 + 1}+x2/{i % 5 + 2})")
        i += 1
    return {"name": "large", "passenger": ["x1", "x2"], "driver": "z", "parameters": {"k": 1},
            "passenger_potential": "k*x1^2 + " + "+".join(terms),
            "driver_potential": "z^2/2", "constraints": [["cos(z)", "sin(z)"]]}


def sweep(cells, step=0.01):
    return {"system": large_system(), "q": [0.1, 0.2, 0.3], "v": [0, 0, 1], "step": step,
            "t_end": 0.01, "methods": ["leapfrog"],
            "axes": [{"path": "params.k", "linspace": [1, 2, cells]}]}


def post(port, path, body, timeout=600):
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", data=json.dumps(body).encode(),
                                 headers={"Content-Type": "application/json"})
    started = time.perf_counter()
    try:
        with urllib.request.urlopen(req, timeout=timeout) as r:
            payload = r.read()
            return r.status, payload, time.perf_counter() - started
    except urllib.error.HTTPError as e:
        return e.code, e.read(), time.perf_counter() - started


def rss_mib(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024
    return float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("server_args", nargs="*")
    args = parser.parse_args()
    port = free_port()
    server = subprocess.Popen([args.binary, "--addr", f"127.0.0.1:{port}", *args.server_args],
                              stderr=subprocess.DEVNULL)
    ok = True
    try:
        for _ in range(100):
            try:
                urllib.request.urlopen(f"http://127.0.0.1:{port}/health", timeout=1).read()
                break
            except OSError:
                time.sleep(0.05)
        idle = rss_mib(server.pid, "VmRSS")

        status, payload, took = post(port, "/sweep", sweep(10_000))
        peak = rss_mib(server.pid, "VmHWM")
        answer_mib = len(payload) / 2**20
        print(f"1. 10^4-cell formula sweep: {status} in {took:.1f} s, answer {answer_mib:.1f} MiB, "
              f"peak RSS {peak:.0f} MiB (idle {idle:.0f} MiB)")
        ok &= status in (200, 422) and took < 30 and peak - idle - answer_mib < 100

        status, payload, took = post(port, "/sweep", sweep(300, step=1e-9))
        print(f"2. over the step limit: {status} in {took * 1e3:.0f} ms: "
              f"{json.loads(payload).get('error', '')[:100]}")
        ok &= status == 422 and took < 2

        small = {"system": "knife_edge", "t_end": 10, "points": 10, "methods": ["leapfrog"]}
        with concurrent.futures.ThreadPoolExecutor(40) as pool:
            big = [pool.submit(post, port, "/sweep", sweep(2000)) for _ in range(2)]
            time.sleep(0.2)
            smalls = []
            for _ in range(32):
                smalls.append(pool.submit(post, port, "/simulate", small))
                time.sleep(0.05)
            answers = [f.result() for f in smalls]
            bigs = [f.result()[0] for f in big]
        statuses = [a[0] for a in answers]
        checking = sum(1 for s, p, _ in answers if s == 503 and b"checking" in p)
        print(f"3. two 2,000-cell sweeps ({bigs}) beside 32 small /simulate: {checking} got 503 "
              f"busy checking, {statuses.count(503) - checking} 503 all slots taken (by design)")
        for f in big:
            s, p, _ = f.result()
            if s != 200:
                print("   sweep:", s, p[:200])
        ok &= checking == 0 and all(f.result()[0] == 200 for f in big)
    finally:
        server.terminate()
        server.wait()
    print("targets met" if ok else "TARGET MISSED")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
