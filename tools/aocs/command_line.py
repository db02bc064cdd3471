"""The command line as typed, for the records that say how a result was made (run.json, campaign.json)."""
from __future__ import annotations

import shlex
import sys


def typed(sub: str) -> str | None:
    """`aocs SUB ARGS...` as this process was started (None when it was not started as `aocs SUB`)."""
    if sub not in sys.argv:
        return None
    return shlex.join(["aocs", sub, *sys.argv[sys.argv.index(sub) + 1:]])

