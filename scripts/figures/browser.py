"""Open a local page in headless Chromium and report what a reader's browser saw: console errors
and uncaught exceptions, every network request other than the page itself (data: and blob: URLs
are the page's own), the value of a JavaScript expression once the page says it is ready, and a
full-page screenshot. Chromium is driven through its DevTools protocol over a pipe
(--remote-debugging-pipe: JSON messages separated by NUL on file descriptors 3 and 4), so no port
and no websocket library are needed.

Uses the standard library only, and the `chromium` executable (Debian's package).
"""
from __future__ import annotations

import base64
import fcntl
import json
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--mute-audio", "--remote-debugging-pipe"]


def executable() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@dataclass
class Visit:
    """What the browser saw of one page."""
    url: str
    console_errors: list = field(default_factory=list)
    requests: list = field(default_factory=list)        # URLs other than the page's own
    value: object = None                                # the expression's value when ready
    ready: bool = False
    screenshot: Path | None = None


class _Pipe:
    def __init__(self, proc, write_fd, read_fd):
        self.proc, self.w = proc, write_fd
        self.events: queue.Queue = queue.Queue()
        self.replies: dict = {}
        self.cond = threading.Condition()
        self.next_id = 0
        threading.Thread(target=self._read, args=(read_fd,), daemon=True).start()

    def _read(self, fd):
        buf = b""
        while True:
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                break
            buf += chunk
            while b"\0" in buf:
                raw, buf = buf.split(b"\0", 1)
                msg = json.loads(raw)
                if "id" in msg:
                    with self.cond:
                        self.replies[msg["id"]] = msg
                        self.cond.notify_all()
                else:
                    self.events.put(msg)

    def send(self, method, params=None, session=None, timeout=30.0):
        self.next_id += 1
        n = self.next_id
        msg = {"id": n, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self.w, json.dumps(msg).encode() + b"\0")
        end = time.monotonic() + timeout
        with self.cond:
            while n not in self.replies:
                if not self.cond.wait(timeout=max(0.0, end - time.monotonic())):
                    raise TimeoutError(f"chromium did not answer {method}")
        reply = self.replies.pop(n)
        if "error" in reply:
            raise RuntimeError(f"{method}: {reply['error']}")
        return reply.get("result", {})


def _local(url: str, page: str) -> bool:
    return url == page or url.split("#")[0] == page or url.startswith(("data:", "blob:", "about:"))


def visit(path, ready="document.body.dataset.chartsDrawn", value=None, screenshot=None, width=1400,
          timeout=90.0) -> Visit:
    """Load the file `path`, wait until the expression `ready` is truthy (or `timeout`), evaluate
    `value` (default: `ready`), take a full-page screenshot into `screenshot` if given."""
    exe = executable()
    if exe is None:
        raise FileNotFoundError("chromium is not on PATH")
    url = Path(path).resolve().as_uri()
    seen = Visit(url)
    to_child_r, to_child_w = os.pipe()
    from_child_r, from_child_w = os.pipe()

    def fds():                 # in the child: its input pipe on 3, its output pipe on 4
        a = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)
        b = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
        os.dup2(a, 3)
        os.dup2(b, 4)

    with tempfile.TemporaryDirectory(prefix="chromium-") as profile:
        proc = subprocess.Popen([exe, *FLAGS, f"--user-data-dir={profile}", "about:blank"],
                                preexec_fn=fds, pass_fds=(3, 4),  # kept open: the dup2s above
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_child_r)
        os.close(from_child_w)
        try:
            cdp = _Pipe(proc, to_child_w, from_child_r)
            target = cdp.send("Target.createTarget", {"url": "about:blank"})["targetId"]
            s = cdp.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
            for domain in ("Runtime", "Log", "Network", "Page"):
                cdp.send(f"{domain}.enable", session=s)
            cdp.send("Emulation.setDeviceMetricsOverride", {"width": width, "height": 900,
                                                            "deviceScaleFactor": 1, "mobile": False}, session=s)
            cdp.send("Page.navigate", {"url": url}, session=s)
            end = time.monotonic() + timeout
            while time.monotonic() < end:
                got = cdp.send("Runtime.evaluate", {"expression": f"Boolean({ready})", "returnByValue": True},
                               session=s)
                if got.get("result", {}).get("value"):
                    seen.ready = True
                    break
                time.sleep(0.2)
            got = cdp.send("Runtime.evaluate", {"expression": value or ready, "returnByValue": True}, session=s)
            seen.value = got.get("result", {}).get("value")
            if screenshot:
                got = cdp.send("Runtime.evaluate", {"expression": "document.documentElement.scrollHeight",
                                                    "returnByValue": True}, session=s)
                height = int(min(got.get("result", {}).get("value") or 900, 16000))
                shot = cdp.send("Page.captureScreenshot", {
                    "format": "png", "captureBeyondViewport": True,
                    "clip": {"x": 0, "y": 0, "width": width, "height": height, "scale": 1}},
                    session=s, timeout=60)
                Path(screenshot).write_bytes(base64.b64decode(shot["data"]))
                seen.screenshot = Path(screenshot)
            time.sleep(0.3)                      # let late console messages and requests arrive
            _drain(cdp, s, seen)
        finally:
            try:
                cdp.send("Browser.close", timeout=5)
            except Exception:
                pass
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            os.close(to_child_w)
            os.close(from_child_r)
    return seen


def _drain(cdp, session, seen: Visit):
    while True:
        try:
            ev = cdp.events.get_nowait()
        except queue.Empty:
            return
        if ev.get("sessionId") != session:
            continue
        m, p = ev.get("method"), ev.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            seen.console_errors.append(" ".join(str(a.get("value", a.get("description", "")))
                                                for a in p.get("args", [])))
        elif m == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            seen.console_errors.append(d.get("exception", {}).get("description") or d.get("text", "exception"))
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            seen.console_errors.append(p["entry"].get("text", ""))
        elif m == "Network.requestWillBeSent":
            u = p.get("request", {}).get("url", "")
            if not _local(u, seen.url):
                seen.requests.append(u)
