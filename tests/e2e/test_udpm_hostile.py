"""A forged LCM fragment on the run's bus (issue 25, item 2): the recording plant's udpm reassembly drops a
fragment claiming a 256 MiB message before allocating it, counts it in its summary and the run's
metrics, and the run and its log are unchanged in size."""
from __future__ import annotations

import json
import socket
import struct
import threading

from aocs import cli
from aocs_wire import netns
from aocs_wire.udpm import MAGIC_LONG, parse_url


def _forger(stop: threading.Event, sent: list):
    group, port, _ = parse_url(netns.LCM_URL)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    # 34 bytes: a fragment 0 of 2 claiming a 256 MiB message on AOCS_SENSORS
    d = struct.pack(">IIIIHH", MAGIC_LONG, 4242, 256 << 20, 0, 0, 2) + b"AOCS_SENSORS\0\0"
    assert len(d) == 34
    while not stop.wait(0.005):
        s.sendto(d, (group, port))
        sent.append(1)
    s.close()


def test_a_forged_256_mib_fragment_is_dropped_counted_and_the_run_is_unchanged(private_netns, capsys, tmp_path):
    stop, sent = threading.Event(), []
    t = threading.Thread(target=_forger, args=(stop, sent), daemon=True)
    t.start()
    try:
        rc = cli.main(["run", "irassi_small", "--duration", "20", "--out", str(tmp_path / "o"), "--no-plots",
                       "-q", "--recorder", "plant", "--json", str(tmp_path / "m.json")])
    finally:
        stop.set()
        t.join()
    capsys.readouterr()
    assert rc == 0 and sent
    m = json.loads((tmp_path / "m.json").read_text())
    assert m["verdict"]["passed"] and m["log_complete"]
    u = m["udpm"]
    assert u["oversize"] >= 1 and u["partial"] == 0 and u["incomplete"] == u["expired"] == 0, u
    assert u["fragments"] == u["oversize"]
    summary = [json.loads(ln)["plant_node"] for ln in (tmp_path / "o" / "plant_node.stdout").read_text().splitlines()
               if ln.startswith('{"plant_node"')][-1]
    assert summary["udpm"] == u
    # the log holds the run's messages only: a 20 s irassi_small log is well under 2 MiB
    assert (tmp_path / "o" / "run.lcmlog").stat().st_size < 2 << 20
