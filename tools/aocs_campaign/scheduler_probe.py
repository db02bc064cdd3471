"""`--scheduler ADDRESS`: the address checked, then the peer asked for its Dask handshake before the client.

    host, port = parse_address("tcp://HOST:PORT")     # CampaignError (one line) when malformed
    probe("tcp://HOST:PORT", timeout_s=10.0)          # CampaignError when not a Dask scheduler

A Dask scheduler speaks first: on accepting a connection it writes its handshake
(distributed.comm.core.Listener.on_connection), one message of the TCP comm's
framing (distributed.comm.tcp.TCP.read: an 8-byte total length, then the frames
with their lengths, distributed.protocol.utils.unpack_frames), a dict with
"compression", "python" and "pickle-protocol". The probe reads it with plain
sockets under one deadline for connect and handshake together
(HANDSHAKE_TIMEOUT_S), a length bound (HANDSHAKE_MAX_BYTES) before it reads
anything, and decodes it with Dask's own loader: a silent listener, an HTTP
server, a peer that sends random bytes are refused in one line, instead of a
client that waits forever or allocates what a random length says.
"""
from __future__ import annotations

import re
import socket
import struct
import time

from .plan import CampaignError

#: connect + handshake, s: a scheduler on a loaded machine answers in milliseconds
HANDSHAKE_TIMEOUT_S = 10.0
#: largest handshake accepted, bytes (a real one is ~100 bytes)
HANDSHAKE_MAX_BYTES = 65536
_ADDRESS = re.compile(r"^(?:tcp://)?(?:\[(?P<v6>[0-9A-Fa-f:.]+)\]|(?P<host>[A-Za-z0-9._-]+)):(?P<port>[0-9]{1,5})$")


def parse_address(text: str) -> tuple[str, int]:
    """(host, port) of tcp://HOST:PORT (or HOST:PORT, [IPv6]:PORT); CampaignError naming the option."""
    m = _ADDRESS.match(text or "")
    if m is None:
        raise CampaignError(f"--scheduler {text!r}: not an address tcp://HOST:PORT")
    port = int(m.group("port"))
    if not 1 <= port <= 65535:
        raise CampaignError(f"--scheduler {text!r}: port {port} out of [1, 65535]")
    return (m.group("v6") or m.group("host")), port


def _read_exactly(sock: socket.socket, n: int, deadline: float) -> bytes:
    buf = bytearray()
    while len(buf) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(min(n - len(buf), 65536))
        if not chunk:
            raise EOFError
        buf += chunk
    return bytes(buf)


def _handshake(sock: socket.socket, deadline: float) -> object:
    from distributed.protocol import loads  # deferred: Dask only for a campaign on a scheduler
    from distributed.protocol.utils import unpack_frames  # deferred: see above

    (total,) = struct.unpack("Q", _read_exactly(sock, 8, deadline))
    if not 8 <= total <= HANDSHAKE_MAX_BYTES:
        raise ValueError(f"a first message of {total} bytes")
    frames, missing = unpack_frames(_read_exactly(sock, total, deadline), partial=True)
    if sum(missing) > HANDSHAKE_MAX_BYTES:
        raise ValueError(f"a first message of {sum(missing)} more bytes")
    frames = list(frames) + [memoryview(_read_exactly(sock, k, deadline)) for k in missing]
    return loads(frames, deserialize=False)


def probe(address: str, timeout_s: float = HANDSHAKE_TIMEOUT_S) -> None:
    """Returns when a Dask scheduler at address sent its handshake within timeout_s; else CampaignError."""
    host, port = parse_address(address)
    deadline = time.monotonic() + timeout_s
    try:
        sock = socket.create_connection((host, port), timeout=timeout_s)
    except OSError as exc:
        raise CampaignError(f"--scheduler {address}: cannot connect ({exc.strerror or exc})") from None
    try:
        msg = _handshake(sock, deadline)
    except TimeoutError:
        raise CampaignError(f"--scheduler {address}: no Dask handshake within {timeout_s:g} s "
                            "(connected, but the peer is silent: not a Dask scheduler?)") from None
    except EOFError:
        raise CampaignError(f"--scheduler {address}: not a Dask scheduler (it closed the connection "
                            "before its handshake)") from None
    except Exception as exc:  # noqa: BLE001 - whatever a foreign peer's bytes make of Dask's decoder
        raise CampaignError(f"--scheduler {address}: not a Dask scheduler (its first bytes are not a Dask "
                            f"handshake: {type(exc).__name__})") from None
    finally:
        sock.close()
    if not (isinstance(msg, dict) and {"compression", "python", "pickle-protocol"} <= set(msg)):
        raise CampaignError(f"--scheduler {address}: not a Dask scheduler (its first message is not a Dask "
                            "handshake)")
