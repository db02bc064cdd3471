"""Start, drive and stop the PIL image under QEMU, with every wait bounded.

    q = Qemu(TARGETS["pil-m7"])
    hello = q.start()                       # boots, checks HELLO (target, precision, counter)
    hdr, payload = q.request(frame.T_STEP, frame.encode_step(...), frame.T_STEP_REPLY)
    bye = q.stop()                          # BYE -> image exits 0; kill if it does not

QEMU runs with its stdin and stdout as pipes and NO chardev for
semihosting, so the image's console reads and writes are plain read(2) /
write(2) on those pipes (firmware/port/cortex-m/pil_link.c explains why a
stdio chardev would lose bytes). `-icount shift=7` makes the guest's SysTick
an instruction counter (firmware/port/cortex-m/pil_icount.h).

Failures raise QemuError subclasses with a message that says what happened:
QemuExited (the process ended: exit status, signal, last stderr lines),
QemuTimeout (no complete reply within the timeout: stalled), ImageError (the
image answered with an ERROR frame), frame.FrameError (a reply that fails its
checks).
"""
from __future__ import annotations

import os
import select
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from aocs_core import paths

from . import frame


@dataclass(frozen=True)
class Target:
    name: str            # --target value
    preset: str          # CMake preset that builds the image
    machine: str         # QEMU board
    target_id: int       # HELLO target field
    real_bytes: int      # sizeof(real_t) of the build
    clock_hz: float      # nominal core clock for ns / us figures (lower bound: 1 instruction per cycle)


TARGETS = {
    "pil-m4f": Target("pil-m4f", "cortex-m4f", "mps2-an386", frame.TARGET_CORTEX_M4F, 4, 168e6),
    "pil-m7": Target("pil-m7", "cortex-m7", "mps2-an500", frame.TARGET_CORTEX_M7, 8, 216e6),
}

#: exit statuses of the image (firmware/port/cortex-m/pil_main.c, startup.S)
EXIT_MEANING = {
    0: "normal end after BYE",
    3: "the image saw EOF on its link (the bridge closed QEMU's stdin)",
    4: "a semihosting read/write failed in the image",
    10: "NMI", 11: "HardFault", 12: "MemManage fault", 13: "BusFault", 14: "UsageFault",
    15: "unexpected exception",
}

#: QEMU's own noise on stderr (the MPS2 boards always have a LAN9118 without a network)
_STDERR_NOISE = ("has no peer",)


class QemuError(RuntimeError):
    """The emulated target failed; the message says how."""


class QemuExited(QemuError):
    pass


class QemuTimeout(QemuError):
    pass


class ImageError(QemuError):
    """The image answered with an ERROR frame."""

    def __init__(self, message: str, error: frame.Error):
        super().__init__(message)
        self.error = error


def image_path(target: Target, override: str | os.PathLike | None = None) -> Path:
    """The ELF to run: override, else <root>/<preset>/aocs_pil.elf in the first of
    aocs_core.paths.pil_build_roots() that has it (the first root when none has)."""
    if override:
        return Path(override)
    roots = paths.pil_build_roots()
    for root in roots:
        if (root / target.preset / "aocs_pil.elf").is_file():
            return root / target.preset / "aocs_pil.elf"
    return roots[0] / target.preset / "aocs_pil.elf"


def describe_exit(code: int | None) -> str:
    if code is None:
        return "still running"
    if code < 0:
        try:
            return f"killed by signal {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit status {code} ({EXIT_MEANING.get(code, 'unknown')})"


class Qemu:
    def __init__(self, target: Target, image: str | os.PathLike | None = None, *, boot_timeout: float = 10.0,
                 reply_timeout: float = 2.0, qemu_bin: str | None = None):
        self.target = target
        self.image = image_path(target, image)
        self.boot_timeout = boot_timeout
        self.reply_timeout = reply_timeout
        self.qemu_bin = qemu_bin or os.environ.get("AOCS_QEMU", "qemu-system-arm")
        self.proc: subprocess.Popen | None = None
        self.hello: frame.Hello | None = None
        self._stderr = None
        self._buf = bytearray()
        self._seq = 0

    # ------------------------------------------------------------------ process
    @property
    def command(self) -> list[str]:
        return [self.qemu_bin, "-M", self.target.machine, "-display", "none", "-nodefaults",
                "-semihosting-config", "enable=on,target=native",
                "-icount", f"shift={frame.ICOUNT_SHIFT}", "-kernel", str(self.image)]

    @property
    def pid(self) -> int | None:
        return self.proc.pid if self.proc is not None else None

    def returncode(self) -> int | None:
        return self.proc.poll() if self.proc is not None else None

    def stderr_tail(self, lines: int = 8) -> str:
        if self._stderr is None:
            return ""
        try:
            self._stderr.flush()
            self._stderr.seek(0)
            text = self._stderr.read().decode("utf-8", "replace")
        except (OSError, ValueError):
            return ""
        keep = [ln for ln in text.splitlines() if ln.strip() and not any(n in ln for n in _STDERR_NOISE)]
        return " | ".join(keep[-lines:])

    def start(self) -> frame.Hello:
        """Boot the image and read its HELLO (bounded by boot_timeout); checks target, precision, counter."""
        if not self.image.is_file():
            raise QemuError(f"PIL image {self.image} not found: build it with "
                            f"`cmake --preset {self.target.preset} && cmake --build --preset {self.target.preset}` "
                            "(or set AOCS_PIL_BUILD_ROOT / --image)")
        self._stderr = tempfile.TemporaryFile()
        try:
            self.proc = subprocess.Popen(self.command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         stderr=self._stderr, bufsize=0, start_new_session=True)
        except OSError as exc:
            raise QemuError(f"cannot start {self.qemu_bin}: {exc}") from exc
        hdr, payload = self._read_frame(self.boot_timeout, "HELLO")
        if hdr.type != frame.T_HELLO:
            raise frame.FrameError(f"first frame from the image is {frame.TYPE_NAMES.get(hdr.type, hdr.type)}, "
                                   "expected HELLO")
        h = frame.Hello.decode(payload)
        t = self.target
        if h.target != t.target_id or h.real_bytes != t.real_bytes:
            raise QemuError(f"{self.image} is a {frame.TARGET_NAMES.get(h.target, h.target)} image with "
                            f"{h.real_bytes}-byte reals, --target {t.name} needs {t.preset} with "
                            f"{t.real_bytes}-byte reals")
        if h.icount_shift != frame.ICOUNT_SHIFT or not h.calib_ok:
            raise QemuError(f"instruction counter calibration failed in the image: measured "
                            f"{h.calib_measured} instructions for {h.calib_expected} (shift {h.icount_shift}; "
                            f"QEMU must run with -icount shift={frame.ICOUNT_SHIFT})")
        self.hello = h
        return h

    # ------------------------------------------------------------------ frames
    def _fail_if_exited(self, what: str) -> None:
        code = self.returncode()
        if code is not None:
            tail = self.stderr_tail()
            raise QemuExited(f"QEMU exited while {what}: {describe_exit(code)}"
                             + (f"; stderr: {tail}" if tail else ""))

    def _fill(self, n: int, deadline: float, what: str) -> None:
        """Read until self._buf holds n bytes, or raise (EOF / exit / timeout)."""
        fd = self.proc.stdout.fileno()
        while len(self._buf) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                self._fail_if_exited(what)
                raise QemuTimeout(f"QEMU did not answer within the timeout while {what} "
                                  f"(got {len(self._buf)} of {n} bytes): the emulator stalled")
            ready, _, _ = select.select([fd], [], [], min(left, 0.25))
            if not ready:
                self._fail_if_exited(what)
                continue
            chunk = os.read(fd, 65536)
            if not chunk:
                try:
                    self.proc.wait(timeout=1.0)
                except subprocess.TimeoutExpired:
                    pass
                self._fail_if_exited(what)
                raise QemuExited(f"QEMU closed its stdout while {what}")
            self._buf += chunk

    def _read_frame(self, timeout: float, what: str) -> tuple[frame.Header, bytes]:
        deadline = time.monotonic() + timeout
        self._fill(frame.HEADER_BYTES, deadline, f"waiting for {what}")
        hdr = frame.decode_header(bytes(self._buf[:frame.HEADER_BYTES]))
        total = frame.HEADER_BYTES + hdr.length + frame.CRC_BYTES
        self._fill(total, deadline, f"waiting for {what}")
        raw = bytes(self._buf[:total])
        del self._buf[:total]
        return frame.check_frame(raw)

    def send_raw(self, data: bytes) -> None:
        """Write bytes to the image (tests use it to inject corrupted frames)."""
        try:
            os.write(self.proc.stdin.fileno(), data)
        except (BrokenPipeError, OSError) as exc:
            try:
                self.proc.wait(timeout=1.0)
            except subprocess.TimeoutExpired:
                pass
            self._fail_if_exited("sending a frame")
            raise QemuExited(f"cannot write to QEMU: {exc}") from exc

    def next_seq(self) -> int:
        self._seq = (self._seq + 1) & 0xFFFFFFFF
        return self._seq

    def read_reply(self, seq: int, expect: int, timeout: float | None = None) -> tuple[frame.Header, bytes]:
        """The reply to request `seq`; ImageError on an ERROR frame, FrameError on a wrong type or seq."""
        name = frame.TYPE_NAMES.get(expect, str(expect))
        hdr, payload = self._read_frame(self.reply_timeout if timeout is None else timeout, f"waiting for {name}")
        if hdr.type == frame.T_ERROR:
            err = frame.Error.decode(payload)
            raise ImageError(f"the image rejected a frame: {err.describe()}", err)
        if hdr.type != expect or hdr.seq != seq:
            raise frame.FrameError(f"expected {name} for seq {seq}, got "
                                   f"{frame.TYPE_NAMES.get(hdr.type, hdr.type)} for seq {hdr.seq}")
        return hdr, payload

    def request(self, ftype: int, payload: bytes, expect: int, timeout: float | None = None):
        seq = self.next_seq()
        self.send_raw(frame.encode(ftype, seq, payload))
        return self.read_reply(seq, expect, timeout)

    # ------------------------------------------------------------------ shutdown
    def stop(self, timeout: float = 2.0) -> frame.Bye | None:
        """BYE (the image reports and exits 0); close, kill whatever is left. Never blocks past timeout."""
        bye = None
        if self.proc is None:
            return None
        if self.proc.poll() is None:
            try:
                _, payload = self.request(frame.T_BYE, b"", frame.T_BYE, timeout=timeout)
                bye = frame.Bye.decode(payload)
            except (QemuError, frame.FrameError, OSError):
                bye = None
        self._close(timeout)
        return bye

    def kill(self) -> None:
        if self.proc is not None:
            self._close(0.0)

    def _close(self, timeout: float) -> None:
        p = self.proc
        for stream in (p.stdin, p.stdout):
            try:
                stream.close()
            except OSError:
                pass
        try:
            p.wait(timeout=max(timeout, 0.0) if timeout > 0 else 0.01)
        except subprocess.TimeoutExpired:
            p.kill()
            try:
                p.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                pass
        if self._stderr is not None:
            pass  # kept open for stderr_tail(); closed by the garbage collector

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc is not None and self.proc.poll() is None:
            self.kill()
