"""Headless Chromium (Debian's `chromium`, installed by scripts/setup.sh) driven over the DevTools protocol with
websocket-client: open a page, collect every console error and uncaught exception, evaluate JavaScript, take a
screenshot. For the HTML reports' browser test (tests/e2e/test_report_browser.py).

    with Browser() as b:
        page = b.open(Path("r.html"), wait_js="window.aocsPlotsDrawn >= 1")
        page.errors            # console errors and exceptions, as text
        page.evaluate("document.title")
        page.screenshot(Path("r.png"))
"""
from __future__ import annotations

import base64
import json
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import websocket

CHROMIUM_NAMES = ("chromium", "chromium-browser")


def chromium() -> str | None:
    return next((p for p in (shutil.which(n) for n in CHROMIUM_NAMES) if p), None)


class BrowserError(RuntimeError):
    pass


class Page:
    def __init__(self, ws: websocket.WebSocket):
        self.ws = ws
        self._id = 0
        self.errors: list[str] = []
        self.console: list[str] = []

    def _handle(self, msg: dict) -> None:
        m, p = msg.get("method"), msg.get("params", {})
        if m == "Runtime.consoleAPICalled":
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
            self.console.append(f"{p.get('type')}: {text}")
            if p.get("type") in ("error", "assert"):
                self.errors.append(f"console.{p.get('type')}: {text}")
        elif m == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            self.errors.append("exception: " + str(d.get("exception", {}).get("description") or d.get("text")))
        elif m == "Log.entryAdded":
            e = p.get("entry", {})
            if e.get("level") == "error":
                self.errors.append(f"log ({e.get('source')}): {e.get('text')} {e.get('url', '')}".rstrip())

    def call(self, method: str, timeout_s: float = 30.0, **params) -> dict:
        self._id += 1
        mid = self._id
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            self.ws.settimeout(max(0.05, end - time.monotonic()))
            msg = json.loads(self.ws.recv())
            if msg.get("id") == mid:
                if "error" in msg:
                    raise BrowserError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self._handle(msg)
        raise BrowserError(f"{method}: no answer in {timeout_s:g} s")

    def evaluate(self, expr: str):
        r = self.call("Runtime.evaluate", expression=expr, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise BrowserError(f"{expr}: {r['exceptionDetails'].get('text')}")
        return r["result"].get("value")

    def wait_for(self, expr: str, timeout_s: float = 60.0) -> bool:
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            if self.evaluate(expr):
                return True
            time.sleep(0.2)
        return False

    def screenshot(self, path: Path) -> Path:
        h = int(self.evaluate("Math.min(document.documentElement.scrollHeight, 8000)") or 1000)
        self.call("Emulation.setDeviceMetricsOverride", width=1400, height=h, deviceScaleFactor=1, mobile=False)
        time.sleep(0.5)
        data = self.call("Page.captureScreenshot", format="png", captureBeyondViewport=True)["data"]
        path.write_bytes(base64.b64decode(data))
        return path


class Browser:
    """One headless Chromium with a throw-away profile; closed (its process group ended) on exit."""

    def __init__(self, timeout_s: float = 30.0):
        self.exe = chromium()
        if self.exe is None:
            raise BrowserError("chromium not found (scripts/setup.sh installs Debian's chromium)")
        self.timeout_s = timeout_s
        self.proc = None
        self.profile = None

    def __enter__(self) -> Browser:
        self.profile = tempfile.mkdtemp(prefix="aocs-chromium-")
        self.proc = subprocess.Popen(
            [self.exe, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
             "--disable-extensions", "--disable-background-networking", "--remote-debugging-port=0",
             "--remote-allow-origins=*", f"--user-data-dir={self.profile}", "--window-size=1400,1000", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        port_file = Path(self.profile) / "DevToolsActivePort"
        end = time.monotonic() + self.timeout_s
        while not (port_file.is_file() and port_file.read_text().strip()):
            if self.proc.poll() is not None or time.monotonic() > end:
                self.__exit__()
                raise BrowserError("chromium did not start its DevTools endpoint")
            time.sleep(0.1)
        self.port = int(port_file.read_text().splitlines()[0])
        return self

    def __exit__(self, *exc) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=10)
        if self.profile:
            shutil.rmtree(self.profile, ignore_errors=True)

    def _new_target(self) -> str:
        import urllib.request  # the DevTools HTTP endpoint, on this machine's loopback

        req = urllib.request.Request(f"http://127.0.0.1:{self.port}/json/new?about:blank", method="PUT")
        with urllib.request.urlopen(req, timeout=10) as r:
            return json.loads(r.read())["webSocketDebuggerUrl"]

    def open(self, path: Path, wait_js: str | None = None, timeout_s: float = 90.0) -> Page:
        ws = websocket.create_connection(self._new_target(), timeout=self.timeout_s, suppress_origin=True)
        page = Page(ws)
        for domain in ("Runtime", "Log", "Page"):
            page.call(f"{domain}.enable")
        page.call("Page.navigate", url=Path(path).resolve().as_uri())
        if not page.wait_for("document.readyState === 'complete'", timeout_s):
            raise BrowserError(f"{path}: the page did not finish loading in {timeout_s:g} s")
        if wait_js and not page.wait_for(wait_js, timeout_s):
            raise BrowserError(f"{path}: `{wait_js}` not true after {timeout_s:g} s; errors: {page.errors}")
        return page


def main(argv=None) -> int:
    """python tests/browser.py PAGE.html ... --shots DIR: each page's console errors, plots drawn and a screenshot."""
    import argparse

    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("pages", nargs="+", type=Path)
    ap.add_argument("--shots", type=Path, default=Path("."))
    args = ap.parse_args(argv)
    args.shots.mkdir(parents=True, exist_ok=True)
    bad = 0
    with Browser() as b:
        for path in args.pages:
            page = b.open(path, wait_js="window.aocsPlotsDrawn === document.querySelectorAll('.plot').length")
            shot = page.screenshot(args.shots / (path.stem + ".png"))
            n = page.evaluate("document.querySelectorAll('.plot').length")
            traces = page.evaluate("Array.from(document.querySelectorAll('.plot')).reduce((a, d) => a + d.data.length, 0)")
            print(f"{path}: {path.stat().st_size / 1e6:.2f} MB, {n} plots drawn, {traces} traces, "
                  f"console errors: {len(page.errors)}{' ' + str(page.errors) if page.errors else ''}; screenshot {shot}")
            bad += bool(page.errors)
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
