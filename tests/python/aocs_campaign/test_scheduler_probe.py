"""`--scheduler` at something that is not a Dask scheduler (issue 25, items 5 and 9): refused in one line
within a stated time, never a hang or a crash. Real peers on loopback in this test process: a silent
listener, an HTTP server, a peer that sends random bytes, a port nobody listens on; and the real Dask
scheduler that must pass. Malformed addresses are refused before any connection."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import threading
import time

import pytest

from aocs_campaign import plan as P
from aocs_campaign import scheduler_probe as S


class Peer:
    """A TCP server on 127.0.0.1 answering every connection with `answer(conn)` in a thread."""

    def __init__(self, answer):
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.answer = answer
        self.conns = []
        self.stop = threading.Event()
        self.sock.settimeout(0.2)
        self.server = threading.Thread(target=self._serve, daemon=True)
        self.server.start()

    def _serve(self):
        while not self.stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except (TimeoutError, OSError):
                continue
            self.conns.append(conn)
            threading.Thread(target=self.answer, args=(conn,), daemon=True).start()

    @property
    def address(self):
        return f"tcp://127.0.0.1:{self.port}"

    def close(self):
        """Stops accepting and closes the listener once no thread is in accept() on it (a listener closed
        under a blocked accept() lives on in the kernel and resets the next connection instead of refusing it)."""
        self.stop.set()
        self.server.join(timeout=10.0)
        for c in self.conns:
            c.close()
        self.sock.close()


def silent(conn):
    time.sleep(60)          # holds the connection open and says nothing


def http(conn):
    conn.settimeout(5)
    try:
        conn.recv(4096)
    except OSError:
        pass
    conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Type: text/plain\r\nContent-Length: 11\r\n\r\nBad Request")
    time.sleep(60)          # keeps it open, like a keep-alive server


def http_first(conn):       # a server that speaks first (e.g. an SMTP or SSH banner)
    conn.sendall(b"SSH-2.0-OpenSSH_9.6\r\n")
    time.sleep(60)


def random_bytes(seed):
    def answer(conn):
        import random

        rng = random.Random(seed)
        try:
            for _ in range(64):
                conn.sendall(bytes(rng.getrandbits(8) for _ in range(1024)))
        except OSError:
            pass
        time.sleep(60)
    return answer


@pytest.fixture
def peer():
    made = []

    def make(answer):
        made.append(Peer(answer))
        return made[-1]
    yield make
    for p in made:
        p.close()


@pytest.mark.parametrize("answer,why", [(http, "not a Dask scheduler"), (http_first, "not a Dask scheduler")]
                         + [(random_bytes(s), "not a Dask scheduler") for s in range(6)])
def test_a_peer_that_is_not_dask_is_refused_in_one_line(peer, answer, why):
    p = peer(answer)
    t0 = time.monotonic()
    with pytest.raises(P.CampaignError, match=why) as exc:
        S.probe(p.address, timeout_s=3.0)
    assert time.monotonic() - t0 < 3.0 + 1.0
    assert "\n" not in str(exc.value) and p.address in str(exc.value)


def test_a_silent_listener_is_refused_after_the_stated_time(peer):
    p = peer(silent)
    t0 = time.monotonic()
    with pytest.raises(P.CampaignError, match=r"no Dask handshake within 1\.5 s") as exc:
        S.probe(p.address, timeout_s=1.5)
    assert 1.4 < time.monotonic() - t0 < 1.5 + 1.0
    assert "\n" not in str(exc.value)
    assert S.HANDSHAKE_TIMEOUT_S == 10.0          # the stated time of `--scheduler` (docs/campaigns.md)


def test_nobody_listening_is_refused(peer):
    p = peer(silent)
    addr = p.address
    p.close()
    with pytest.raises(P.CampaignError, match="cannot connect"):
        S.probe(addr, timeout_s=2.0)


@pytest.mark.parametrize("text", ["tcp://", "tcp://host", "tcp://127.0.0.1:", "tcp://127.0.0.1:99999",
                                  "tcp://127.0.0.1:0", "tcp://127.0.0.1:x", "http://127.0.0.1:8786", "::::",
                                  "tcp://[::1:8786", "tcp://a b:1", "", "tcp://127.0.0.1:8786/path", "\x00:1"])
def test_malformed_addresses_are_refused(text):
    with pytest.raises(P.CampaignError, match="--scheduler") as exc:
        S.parse_address(text)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("text,host,port", [("tcp://127.0.0.1:8786", "127.0.0.1", 8786),
                                            ("127.0.0.1:8786", "127.0.0.1", 8786),
                                            ("tcp://node-3.cluster:1", "node-3.cluster", 1),
                                            ("tcp://[::1]:8786", "::1", 8786)])
def test_good_addresses(text, host, port):
    assert S.parse_address(text) == (host, port)


def test_a_real_dask_scheduler_passes(tmp_path):
    from dask.distributed import Scheduler  # noqa: F401 - the real one, started as its own process

    f = tmp_path / "s.json"
    proc = subprocess.Popen([os.path.join(os.path.dirname(sys.executable), "dask"), "scheduler", "--host",
                             "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file", str(f)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        end = time.monotonic() + 60
        while not f.is_file():
            assert time.monotonic() < end and proc.poll() is None
            time.sleep(0.1)
        import json

        time.sleep(0.2)
        S.probe(json.loads(f.read_text())["address"], timeout_s=10.0)
    finally:
        proc.terminate()
        proc.wait(20)


@pytest.mark.parametrize("answer", [http, random_bytes(1)])
def test_cli_refuses_a_scheduler_that_is_not_dask_with_exit_2(peer, tmp_path, answer):
    p = peer(answer)
    r = subprocess.run([sys.executable, "-m", "aocs.cli", "campaign", "irassi_large", "--runs", "2", "--seed", "1",
                        "--scheduler", p.address, "--out", str(tmp_path / "mc"), "-q"],
                       capture_output=True, text=True, timeout=120)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and "not a Dask scheduler" in lines[0], r.stderr


def test_cli_refuses_a_malformed_address_before_anything(tmp_path):
    r = subprocess.run([sys.executable, "-m", "aocs.cli", "campaign", "irassi_large", "--runs", "2", "--seed", "1",
                        "--scheduler", "tcp://127.0.0.1:99999", "--out", str(tmp_path / "mc"), "-q"],
                       capture_output=True, text=True, timeout=120)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and "--scheduler" in lines[0], r.stderr
    assert not (tmp_path / "mc").exists()
