"""The one exception type of the API: its message is the line the command line prints after `aocs CMD: KIND:`."""
from __future__ import annotations

from pathlib import Path

#: the command line's exit codes (cmd_run, cmd_compare, cmd_campaign); EXIT_IO: an I/O failure (a full disk, a
#: read-only or vanished folder): the user's options are fine, the machine is not
EXIT_FAILED, EXIT_USAGE, EXIT_IO, EXIT_INTERRUPTED = 1, 2, 3, 130


class AocsError(Exception):
    """kind: "error" (bad input, exit 2; an I/O failure, exit 3), "FAILED" (a process failed, exit 1), "aborted" (a signal, exit 1) or
    "INCOMPLETE" (an interrupted campaign, exit 130)."""

    def __init__(self, message: str, kind: str = "error", exit_code: int = EXIT_USAGE):
        super().__init__(message)
        self.kind = kind
        self.exit_code = exit_code

    def line(self, command: str) -> str:
        """What the command line prints: `aocs run: error: ...`."""
        return f"aocs {command}: {self.kind}: {self}"


def usage(exc: BaseException) -> AocsError:
    return AocsError(str(exc), "error", EXIT_USAGE)


def failed(exc: BaseException) -> AocsError:
    return AocsError(str(exc), "FAILED", EXIT_FAILED)


def io_failure(exc: OSError, folder=None, note: str = "") -> AocsError:
    """'I/O failure on FILE: No space left on device' (the file when the error names one, else the folder the
    command was writing into), exit EXIT_IO."""
    where = f" on {exc.filename}" if exc.filename else (f" writing into {folder}" if folder else "")
    return AocsError(f"I/O failure{where}: {exc.strerror or exc}{note}", "error", EXIT_IO)


def check_output_file(option: str, path) -> None:
    """Refuses an output file that cannot be written (AocsError naming the option), before any work."""
    if path is None:
        return
    p = Path(path)
    if p.is_dir():
        raise AocsError(f"{option} {p}: is a folder, not a file")
    if not p.resolve().parent.is_dir():
        raise AocsError(f"{option} {p}: folder {p.parent} does not exist")
