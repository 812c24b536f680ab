"""The HTTP server the Python API is compared with: the `nhlab` binary of this checkout
(`NHLAB_BINARY`, else target/debug/nhlab, which `cargo test` builds) on a free loopback
port, for the whole session."""

import json
import os
import re
import subprocess
import time
import urllib.error
import urllib.request

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class Http:
    def __init__(self, url):
        self.url = url

    def call(self, method, path, body=None, accept="application/json"):
        """(status, parsed JSON or text)."""
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.url + path, data=data, method=method)
        req.add_header("accept", accept)
        if data is not None:
            req.add_header("content-type", "application/json")
        try:
            with urllib.request.urlopen(req, timeout=300) as r:
                status, text = r.status, r.read().decode()
        except urllib.error.HTTPError as e:
            status, text = e.code, e.read().decode()
        return status, (json.loads(text) if accept == "application/json" else text)


@pytest.fixture(scope="session")
def http():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    binary = os.environ.get("NHLAB_BINARY", os.path.join(target, "debug", "nhlab"))
    if not os.access(binary, os.X_OK):
        pytest.fail(f"no nhlab binary at {binary}: cargo build -p nhlab-server, or set NHLAB_BINARY")
    log = open(os.path.join(os.environ.get("TMPDIR", "/tmp"), f"nhlab-pytest-{os.getpid()}.log"), "w+")
    proc = subprocess.Popen([binary, "--addr", "127.0.0.1:0"], stderr=log, stdout=subprocess.DEVNULL)
    url = None
    for _ in range(200):
        log.seek(0)
        m = re.search(r"listening on (http://[0-9.:]+)", log.read())
        if m:
            url = m.group(1)
            break
        time.sleep(0.05)
    if url is None:
        proc.kill()
        pytest.fail("the nhlab server did not start")
    yield Http(url)
    proc.terminate()
    proc.wait(timeout=15)
