#!/usr/bin/env python3
"""Soak: the server under every kind of abuse at once, to show it cannot be starved.

Starts the given server binary on a free loopback port (extra arguments are passed to it)
and, for DURATION seconds (default 60), runs at once:
  - 50 clients of mixed requests (small /simulate as JSON and as a stream, /scorecard of one
    scene, /work-precision, GET /systems), each retrying a 503 after its Retry-After;
  - 100 slow clients sending a request head one byte a second, reconnecting when cut off;
  - 20 streams that are requested and never read (each a long run with many points, so its
    events soon fill the socket's buffers), reopened when the server closes them;
  - a flood of checks that compute: 250 at a time, each a scene whose latitude axis is not
    cached (a new q each time), asking for a short run;
  - 4 clients of systems given as formulas: a 10⁴-cell sweep over a parameter of a
    ~1,950-character U (one step a cell), the same sweep over the step limit, 16 heavy
    DLA∘p8s15 runs at the step limit (refused with their price), and a heavy DLA∘p8s15 run
    that is admitted and abandoned by its client after 0.3 s;
  - a prober, in a process of its own: GET /health every 50 ms, timing each answer.
Then it closes every client and waits for the slots to be free.

It reports the statuses seen (503s apart: a busy server says so, by design), the server's
peak RSS (VmHWM), /health's latency percentiles, and how long the slots took to be free
after the end, and exits non-zero if a target is missed: no 5xx but 503, peak RSS under
512 MiB, /health p99 under 100 ms, every slot free within 5 s.

  cargo build --release -p nhlab-server
  python3 bench/soak.py target/release/nhlab [--duration 60] [-- --max-simulations 2 ...]
"""

import argparse
import asyncio
import collections
import json
import multiprocessing
import random
import socket
import subprocess
import sys
import time

from formula_sweep import large_system, sweep as formula_sweep

MIXED = 50
SLOW = 100
STALLED = 20
FLOOD = 250
FORMULA = 4


def heavy_run(runs, t_end):
    """`runs` DLA∘p8s15 runs on a heavy smooth U of the large system's kind."""
    return {"system": large_system(), "q": [0.1, 0.2, 0.3], "v": [0, 0, 1], "step": 0.01,
            "t_end": t_end, "points": 10,
            "methods": [{"id": "dla", "composition": "p8s15"}] * runs}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Soak:
    def __init__(self, port, duration):
        self.port = port
        self.end = time.monotonic() + duration
        self.statuses = collections.Counter()
        self.by_kind = collections.defaultdict(collections.Counter)
        self.errors = collections.Counter()
        self.health_ms = []
        self.health_failures = 0
        self.writers = set()

    def running(self):
        return time.monotonic() < self.end

    async def connect(self):
        reader, writer = await asyncio.open_connection("127.0.0.1", self.port)
        self.writers.add(writer)
        return reader, writer

    def close(self, writer):
        self.writers.discard(writer)
        writer.close()

    async def request(self, method, path, body=None, accept="application/json", read=True):
        """One request on a new connection: the status and the body (read to the end)."""
        reader, writer = await self.connect()
        try:
            data = json.dumps(body).encode() if body is not None else b""
            head = (
                f"{method} {path} HTTP/1.1\r\nHost: soak\r\nAccept: {accept}\r\n"
                f"Connection: close\r\n"
            )
            if body is not None:
                head += f"Content-Type: application/json\r\nContent-Length: {len(data)}\r\n"
            writer.write(head.encode() + b"\r\n" + data)
            await writer.drain()
            status_line = await reader.readline()
            status = int(status_line.split()[1]) if status_line else 0
            headers = {}
            while True:
                line = await reader.readline()
                if line in (b"\r\n", b""):
                    break
                k, _, v = line.decode().partition(":")
                headers[k.strip().lower()] = v.strip()
            payload = await reader.read() if read else b""
            return status, headers, payload
        finally:
            self.close(writer)

    async def mixed(self, rng):
        scene = {"system": "knife_edge", "preset": "paper-perturbed", "t_end": 200}
        choices = [
            ("POST", "/simulate", {**scene, "points": 500}, "application/json"),
            ("POST", "/simulate", {**scene, "points": 500}, "text/event-stream"),
            ("POST", "/scorecard", {"scenes": [scene], "methods": ["leapfrog", "dd"]},
             "application/json"),
            ("POST", "/work-precision", {**scene, "t_end": 20, "levels": 3, "repeats": 1,
                                         "methods": ["leapfrog"]}, "application/json"),
            ("GET", "/systems", None, "application/json"),
        ]
        while self.running():
            method, path, body, accept = rng.choice(choices)
            try:
                status, headers, _ = await self.request(method, path, body, accept)
            except (OSError, asyncio.IncompleteReadError, ValueError, IndexError) as e:
                self.errors[f"mixed {path}: {type(e).__name__}"] += 1
                await asyncio.sleep(0.1)
                continue
            self.statuses[status] += 1
            self.by_kind[f"{method} {path} {accept}"][status] += 1
            if status == 503:
                await asyncio.sleep(float(headers.get("retry-after", "1")))

    async def slow(self):
        head = b"POST /simulate HTTP/1.1\r\nHost: soak\r\nContent-Type: application/json\r\n"
        while self.running():
            try:
                _, writer = await self.connect()
            except OSError:
                self.errors["slow: connect"] += 1
                await asyncio.sleep(1)
                continue
            try:
                for byte in head:
                    if not self.running():
                        break
                    writer.write(bytes([byte]))
                    await writer.drain()
                    await asyncio.sleep(1)
            except OSError:
                pass  # cut off by the header timeout, as it should be: reconnect
            finally:
                self.close(writer)

    async def stalled(self):
        body = json.dumps({"system": "cvt_pendulum", "preset": "rotating", "t_end": 2e7,
                           "points": 20000, "methods": ["leapfrog"]}).encode()
        while self.running():
            try:
                reader, writer = await self.connect()
                writer.write(
                    b"POST /simulate HTTP/1.1\r\nHost: soak\r\nAccept: text/event-stream\r\n"
                    b"Content-Type: application/json\r\nContent-Length: "
                    + str(len(body)).encode() + b"\r\n\r\n" + body)
                await writer.drain()
            except OSError:
                await asyncio.sleep(1)
                continue
            # Never read; wait until the server gives up on us (or the soak ends).
            while self.running() and not reader.at_eof():
                await asyncio.sleep(0.5)
                if writer.is_closing():
                    break
            self.close(writer)
            await asyncio.sleep(0.5)

    async def flood(self, rng):
        while self.running():
            q = [rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 1)]
            body = {"system": "cvt_pendulum", "preset": "oscillating-perturbed", "q": q,
                    "t_end": 1, "methods": ["leapfrog"], "points": 10}
            try:
                status, headers, _ = await self.request("POST", "/simulate", body)
            except (OSError, asyncio.IncompleteReadError, ValueError, IndexError) as e:
                self.errors[f"flood: {type(e).__name__}"] += 1
                continue
            self.statuses[status] += 1
            self.by_kind["flood of checks"][status] += 1

    async def formula(self, rng):
        choices = [
            ("formula sweep 10^4 cells", formula_sweep(10_000, 0.01)),
            ("formula sweep over the step limit", formula_sweep(300, 1e-9)),
            ("16 heavy runs at the step limit", heavy_run(16, 13_300.0)),
            ("heavy run, client leaves", heavy_run(1, 100.0)),
        ]
        while self.running():
            kind, body = rng.choice(choices)
            path = "/sweep" if "sweep" in kind else "/simulate"
            try:
                if kind.endswith("leaves"):
                    await self.abandon(path, body, 0.3)
                    self.by_kind[kind]["left"] += 1
                    continue
                status, headers, _ = await self.request("POST", path, body)
            except (OSError, asyncio.IncompleteReadError, ValueError, IndexError) as e:
                self.errors[f"formula {kind}: {type(e).__name__}"] += 1
                await asyncio.sleep(0.1)
                continue
            self.statuses[status] += 1
            self.by_kind[kind][status] += 1
            if status == 503:
                await asyncio.sleep(float(headers.get("retry-after", "1")))

    async def abandon(self, path, body, after):
        """Sends a request and closes the connection `after` s later, unread."""
        _, writer = await self.connect()
        try:
            data = json.dumps(body).encode()
            writer.write(
                f"POST {path} HTTP/1.1\r\nHost: soak\r\nContent-Type: application/json\r\n"
                f"Content-Length: {len(data)}\r\n\r\n".encode() + data)
            await writer.drain()
            await asyncio.sleep(after)
        finally:
            self.close(writer)

    async def run(self):
        tasks = [self.mixed(random.Random(i)) for i in range(MIXED)]
        tasks += [self.slow() for _ in range(SLOW)]
        tasks += [self.stalled() for _ in range(STALLED)]
        tasks += [self.flood(random.Random(1000 + i)) for i in range(FLOOD)]
        tasks += [self.formula(random.Random(2000 + i)) for i in range(FORMULA)]
        await asyncio.gather(*tasks)
        for writer in list(self.writers):
            self.close(writer)


def probe(port, duration, out):
    """GET /health every 50 ms for `duration` s, in a process of its own (so that the
    clients' event loop does not delay it): the latencies in ms, -1 for a failure."""
    end = time.monotonic() + duration
    latencies = []
    while time.monotonic() < end:
        start = time.perf_counter()
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
                s.sendall(b"GET /health HTTP/1.1\r\nHost: soak\r\nConnection: close\r\n\r\n")
                data = b""
                while chunk := s.recv(65536):
                    data += chunk
            ok = data.startswith(b"HTTP/1.1 200")
            latencies.append((time.perf_counter() - start) * 1e3 if ok else -1)
        except OSError:
            latencies.append(-1)
        time.sleep(0.05)
    out.put(latencies)


def health(port):
    s = Soak(port, 0)
    status, _, payload = asyncio.run(s.request("GET", "/health"))
    return json.loads(payload) if status == 200 else None


def peak_rss_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def percentile(xs, p):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(p / 100 * len(xs)))] if xs else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("--duration", type=float, default=60)
    parser.add_argument("server_args", nargs="*")
    args = parser.parse_args()
    port = free_port()
    server = subprocess.Popen([args.binary, "--addr", f"127.0.0.1:{port}", *args.server_args],
                              stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            try:
                if health(port):
                    break
            except OSError:
                time.sleep(0.1)
        soak = Soak(port, args.duration)
        results = multiprocessing.Queue()
        prober = multiprocessing.Process(target=probe, args=(port, args.duration, results))
        prober.start()
        asyncio.run(soak.run())
        latencies = results.get()
        prober.join()
        soak.health_ms = [x for x in latencies if x >= 0]
        soak.health_failures = sum(1 for x in latencies if x < 0)
        ended = time.monotonic()
        while True:
            h = health(port)
            if h and h["simulations"] == 0 and h["active_runs"] == 0:
                free_after = time.monotonic() - ended
                break
            if time.monotonic() - ended > 60:
                free_after = float("inf")
                break
            time.sleep(0.05)
        rss = peak_rss_mib(server.pid)
        alive = server.poll() is None
    finally:
        server.terminate()
        server.wait(timeout=30)
    five = {s: n for s, n in soak.statuses.items() if 500 <= s < 600 and s != 503}
    p50, p99 = percentile(soak.health_ms, 50), percentile(soak.health_ms, 99)
    report = {
        "duration_s": args.duration,
        "statuses": dict(sorted(soak.statuses.items())),
        "by_kind": {k: dict(sorted(v.items())) for k, v in sorted(soak.by_kind.items())},
        "client_errors": dict(soak.errors),
        "health": {"answers": len(soak.health_ms), "failures": soak.health_failures,
                   "p50_ms": round(p50, 2), "p99_ms": round(p99, 2),
                   "max_ms": round(max(soak.health_ms, default=float("nan")), 2)},
        "peak_rss_mib": round(rss, 1),
        "slots_free_after_s": round(free_after, 2),
        "server_alive": alive,
    }
    print(json.dumps(report, indent=2))
    missed = []
    if five:
        missed.append(f"5xx other than 503: {five}")
    if rss >= 512:
        missed.append(f"peak RSS {rss:.0f} MiB")
    if not p99 < 100 or soak.health_failures:
        missed.append(f"/health p99 {p99:.1f} ms, {soak.health_failures} failures")
    if not free_after <= 5:
        missed.append(f"slots free after {free_after} s")
    if not alive:
        missed.append("the server died")
    for m in missed:
        print("MISSED:", m, file=sys.stderr)
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
