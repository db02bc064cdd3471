"""A thread that enters a fresh network namespace (a campaign run, the API's run thread, worker.netns_check's
probe) leaves AOCS_NETNS, the variable that tells this process's children which namespace is ours, naming the
main thread's: before, the probe's throw-away namespace ended up in it, and every later child of the process
(plant_node, the PIL bridge) refused to open udpm 'outside a private network namespace'."""
from __future__ import annotations

import os
import subprocess
import sys
import threading

from aocs_wire import netns


def test_a_thread_s_fresh_namespace_does_not_rename_the_process_s(private_netns):
    before = os.environ[netns.ENV_VAR]
    assert netns.in_netns() and before == netns.current_netns_id()
    seen = {}

    def enter():
        seen["ns"] = netns.enter_netns(fresh=True)
        seen["in"] = netns.in_netns()

    t = threading.Thread(target=enter)
    t.start()
    t.join()
    assert seen["in"] and seen["ns"] != before          # the thread is in a namespace of its own
    assert os.environ[netns.ENV_VAR] == before          # the process's variable still names the main thread's
    # and a child started from the main thread still knows it runs in one of ours
    code = "from aocs_wire import netns; print(netns.in_netns())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "True"
