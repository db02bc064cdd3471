"""The error every design check raises: here, apart from the checks themselves (scipy), so a module
that only needs to catch it (the runner's run-start designs) does not pay for scipy's import."""
from __future__ import annotations


class DesignError(RuntimeError):
    """A design check failed; no table may be written."""
