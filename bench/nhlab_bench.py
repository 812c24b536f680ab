"""Shared helpers of the bench/*.py scripts (Python 3 standard library only).

- `Server`: builds the release binary (`cargo build --release -p nhlab-server`), starts
  target/release/nhlab on 127.0.0.1 (port 0 = ephemeral, or a given one) with extra flags,
  waits for its "listening on" line, and stops it (SIGTERM, then SIGKILL) on exit, on Ctrl-C
  and on SIGTERM.
- `post_json`, `stream`: one POST /simulate as JSON, or as server-sent events read to the end
  (every event, parsed), with the client's wall time.
- `rss_kib`, `hwm_kib`, `reset_hwm`, `cpu_seconds`, `thread_cpu_ns`: the server's memory and
  CPU from /proc.

Only loopback traffic.
"""

import atexit
import http.client
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(*args):
    print(*args, file=sys.stderr, flush=True)


def build(skip=False):
    """Builds the release server; returns the binary's path."""
    if not skip:
        log("building: cargo build --release -p nhlab-server")
        subprocess.run(
            ["cargo", "build", "--release", "--quiet", "-p", "nhlab-server"], cwd=ROOT, check=True
        )
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    binary = os.path.join(target, "release", "nhlab")
    if not os.access(binary, os.X_OK):
        sys.exit(f"no release binary at {binary}")
    return binary


class Server:
    """The release server on loopback, stopped when the script ends however it ends."""

    def __init__(self, binary, flags=(), port=0):
        self.log_path = f"/tmp/nhlab-bench-{os.getpid()}-{id(self)}.log"
        self.log_file = open(self.log_path, "w+")
        cmd = [binary, "--addr", f"127.0.0.1:{port}", *flags]
        log("starting:", " ".join(cmd))
        env = {**os.environ, "RUST_LOG": "info"}
        self.proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=self.log_file, env=env)
        self.pid = self.proc.pid
        atexit.register(self.stop)
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(sig, _exit_on_signal)
        self.host, self.port = None, None
        for _ in range(200):
            with open(self.log_path) as f:
                m = re.search(r"listening on http://([0-9.]+):(\d+)", f.read())
            if m:
                self.host, self.port = m.group(1), int(m.group(2))
                break
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        if self.port is None:
            with open(self.log_path) as f:
                log(f.read())
            self.stop()
            sys.exit("the server did not start")
        assert self.host == "127.0.0.1"
        log(f"server pid {self.pid} on http://{self.host}:{self.port}")

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log_file.close()
        if os.path.exists(self.log_path):
            os.remove(self.log_path)

    def connection(self, timeout=600):
        return http.client.HTTPConnection(self.host, self.port, timeout=timeout)

    def get(self, path):
        c = self.connection()
        c.request("GET", path)
        r = c.getresponse()
        body = r.read()
        c.close()
        return json.loads(body)


def _exit_on_signal(signum, _frame):
    # Runs the atexit handlers (which stop the server).
    sys.exit(128 + signum)


def post_json(server, body, path="/simulate"):
    """POST `path` as JSON: (status, parsed body, client wall seconds)."""
    data = json.dumps(body).encode()
    c = server.connection()
    t0 = time.perf_counter()
    c.request("POST", path, data, {"content-type": "application/json"})
    r = c.getresponse()
    raw = r.read()
    wall = time.perf_counter() - t0
    c.close()
    return r.status, json.loads(raw), wall


class StreamResult:
    def __init__(self):
        self.events = []  # (name, parsed data), in order
        self.wall = None  # seconds from sending the request to the end of the body
        self.bytes = 0

    def of(self, name):
        return [d for n, d in self.events if n == name]

    def series(self, run):
        """Concatenated `points` of run `run`: {integral: {"t": [...], "mean": [...], "max": [...]}}."""
        out = {}
        for d in self.of("points"):
            if d["run"] != run:
                continue
            s = out.setdefault(d["integral"], {"t": [], "mean": [], "max": []})
            for k in ("t", "mean", "max"):
                s[k].extend(d[k])
        return out


def stream(server, body, parse=True):
    """POST /simulate with Accept: text/event-stream, reading every event to the end.

    With parse=False the events are only split, not decoded (a lighter client)."""
    data = json.dumps(body).encode()
    res = StreamResult()
    c = server.connection()
    t0 = time.perf_counter()
    c.request(
        "POST",
        "/simulate",
        data,
        {"content-type": "application/json", "accept": "text/event-stream"},
    )
    r = c.getresponse()
    if r.status != 200:
        raise RuntimeError(f"stream answered {r.status}: {r.read()[:500]!r}")
    name, lines = None, []
    while True:
        line = r.readline()
        if not line:
            break
        res.bytes += len(line)
        line = line.rstrip(b"\r\n")
        if not line:
            if lines or name:
                payload = b"\n".join(lines)
                res.events.append((name, json.loads(payload) if parse and payload else payload))
            name, lines = None, []
        elif line.startswith(b"event:"):
            name = line[6:].strip().decode()
        elif line.startswith(b"data:"):
            lines.append(line[5:].lstrip(b" ") if line[5:6] == b" " else line[5:])
        # comments (keep-alive) and other fields are ignored
    res.wall = time.perf_counter() - t0
    c.close()
    return res


def _status_kib(pid, field):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return None


def rss_kib(pid):
    return _status_kib(pid, "VmRSS")


def hwm_kib(pid):
    return _status_kib(pid, "VmHWM")


def reset_hwm(pid):
    """Resets the process's peak RSS (VmHWM) to its current RSS; False if not permitted."""
    try:
        with open(f"/proc/{pid}/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def cpu_seconds(pid):
    """User + system CPU time of the whole process (all threads, dead ones included)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    # fields[0] is field 3 (state); utime and stime are fields 14 and 15.
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def thread_cpu_ns(pid):
    """CPU time of the process's live threads, in nanoseconds (per-thread schedstat: exact,
    where `cpu_seconds` counts clock ticks). Returns (ns, thread ids): a thread that ended
    between two readings takes its time with it, so compare the ids too."""
    total, tids = 0, set()
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{tid}/schedstat") as f:
                total += int(f.read().split()[0])
            tids.add(tid)
        except OSError:
            pass
    return total, tids


class RssSampler:
    """Samples VmRSS of `pid` every `interval` seconds in a thread, until stopped."""

    def __init__(self, pid, interval=1.0):
        self.pid, self.interval = pid, interval
        self.samples = []  # (seconds since start, KiB)
        self._stop = threading.Event()
        self._t0 = time.perf_counter()
        self.samples.append((0.0, rss_kib(pid)))
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stop.wait(self.interval):
            self.samples.append((time.perf_counter() - self._t0, rss_kib(self.pid)))

    def stop(self):
        self._stop.set()
        self._thread.join()
        self.samples.append((time.perf_counter() - self._t0, rss_kib(self.pid)))
        return self.samples


def other_load():
    """What else is using the CPU: load average and the busiest other processes."""
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    try:
        top = subprocess.run(
            ["ps", "-eo", "pcpu,comm", "--sort=-pcpu", "--no-headers"],
            capture_output=True,
            text=True,
            timeout=5,
        ).stdout.splitlines()[:4]
        top = ", ".join(" ".join(line.split()) for line in top)
    except (OSError, subprocess.SubprocessError):
        top = "?"
    return f"load average {load}; busiest processes (%CPU since start): {top}"


def _cpu_times():
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    idle = v[3] + v[4]  # idle + iowait
    return sum(v), idle


def busy_fraction(window=0.3):
    """Fraction of all cores busy during the next `window` seconds (whoever uses them)."""
    t0, i0 = _cpu_times()
    time.sleep(window)
    t1, i1 = _cpu_times()
    return 1 - (i1 - i0) / max(1, t1 - t0)


class Quiet:
    """On a shared machine: waits before each measurement until the cores are nearly idle
    (busy ≤ `max_busy` over 0.3 s), at most `timeout` seconds, and counts the measurements
    that had to start anyway."""

    def __init__(self, max_busy=0.15, timeout=60.0):
        self.max_busy, self.timeout = max_busy, timeout
        self.waited, self.loaded, self.count = 0.0, 0, 0

    def wait(self):
        if self.max_busy >= 1:
            return
        t0 = time.perf_counter()
        self.count += 1
        while True:
            busy = busy_fraction()
            if busy <= self.max_busy:
                break
            if time.perf_counter() - t0 > self.timeout:
                self.loaded += 1
                break
        self.waited += time.perf_counter() - t0

    def report(self):
        return (
            f"{self.count} measurements, each started once the cores were ≤ "
            f"{self.max_busy:.0%} busy over 0.3 s (waited {self.waited:.0f} s in all; "
            f"{self.loaded} started after {self.timeout:.0f} s under load anyway)"
        )


def median(xs):
    s = sorted(xs)
    n = len(s)
    return s[n // 2] if n % 2 else (s[n // 2 - 1] + s[n // 2]) / 2
