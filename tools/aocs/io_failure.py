"""Exit status and one line for an I/O failure (a full disk, a read-only or vanished folder) of a
sub-command: exit EXIT_IO = 3, not 2 (bad input: the user's options are fine, the machine is not)."""
from __future__ import annotations

EXIT_IO = 3


def message(exc: OSError, folder=None) -> str:
    """'I/O failure on FILE: No space left on device' (the file when the error names one, else the folder
    the command was writing into)."""
    where = f" on {exc.filename}" if exc.filename else (f" writing into {folder}" if folder else "")
    return f"I/O failure{where}: {exc.strerror or exc}"
