"""Headless Chromium for the report tests: load a page, collect console errors, take screenshots.

Talks the DevTools protocol over --remote-debugging-pipe (NUL-terminated JSON on file descriptors 3 and
4 of the browser), so it needs no Python package beyond the standard library. The browser runs with
the network cut off (every host resolves to nothing, a dead proxy): a page that is not self-contained
shows up as a failed request. PNG screenshots are decoded by a minimal decoder (png_pixels).
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import shutil
import struct
import subprocess
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-extensions", "--disable-default-apps", "--mute-audio", "--hide-scrollbars",
         # WebGL on the CPU: the 3D view needs it where there is no GPU.
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         # No network: any request leaving the page fails (and is reported).
         "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9", "--remote-debugging-pipe")
LOCAL_SCHEMES = ("file:", "data:", "blob:", "about:", "chrome-error:")
# Messages a headless software renderer prints about itself, not about the page.
BENIGN = ("GPU stall due to ReadPixels", "Automatic fallback to software WebGL", "willReadFrequently")


def find_browser() -> str | None:
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    return None


@dataclass
class PageLoad:
    """What loading a page showed: console errors, uncaught exceptions, requests off the machine."""

    errors: list[str] = field(default_factory=list)
    requests: list[str] = field(default_factory=list)


class Browser:
    """One headless browser with one tab; use as a context manager."""

    def __init__(self, executable: str, width: int = 1400, height: int = 1000, timeout: float = 60.0):
        self.width, self.height, self.timeout = width, height, timeout
        self._profile = tempfile.mkdtemp(prefix="winder-chromium-")
        to_browser, self._send = os.pipe()
        self._recv, from_browser = os.pipe()
        child_in, child_out = (fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in (to_browser, from_browser))

        def fds() -> None:  # in the child, before exec
            os.dup2(child_in, 3)
            os.dup2(child_out, 4)

        self._proc = subprocess.Popen([executable, *FLAGS, f"--user-data-dir={self._profile}", "about:blank"],
                                      stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL, pass_fds=(3, 4), preexec_fn=fds)
        for fd in (to_browser, from_browser, child_in, child_out):
            os.close(fd)
        self._buffer = b""
        self._next_id = 0
        self._events: list[dict] = []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self._session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(f"{domain}.enable", session=True)
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=width, height=height,
                  deviceScaleFactor=1, mobile=False)

    # -- protocol -----------------------------------------------------------------------------------
    def _read(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("the browser did not answer")
            chunk = os.read(self._recv, 1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed the DevTools pipe")
            self._buffer += chunk
        text, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(text)

    def call(self, method: str, session: bool = False, **params) -> dict:
        self._next_id += 1
        msg = {"id": self._next_id, "method": method, "params": params}
        if session:
            msg["sessionId"] = self._session
        os.write(self._send, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._read(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self._events.append(reply)

    def evaluate(self, expression: str):
        res = self.call("Runtime.evaluate", session=True, expression=expression, returnByValue=True,
                        awaitPromise=True)
        if "exceptionDetails" in res:
            raise RuntimeError(f"{expression}: {res['exceptionDetails'].get('text')}")
        return res["result"].get("value")

    # -- pages --------------------------------------------------------------------------------------
    def load(self, path: Path, ready: str, settle: float = 1.0) -> PageLoad:
        """Open a file, wait until the JavaScript expression ready is true (then settle seconds for
        WebGL to draw), and return what the console and the network saw."""
        self._events.clear()
        self.call("Page.navigate", session=True, url=Path(path).resolve().as_uri())
        deadline = time.monotonic() + self.timeout
        while not self.evaluate(f"document.readyState === 'complete' && Boolean({ready})"):
            if time.monotonic() > deadline:
                raise TimeoutError(f"{path}: not ready after {self.timeout:g} s ({ready})")
            time.sleep(0.1)
        time.sleep(settle)
        return self.seen()

    def seen(self) -> PageLoad:
        """What the console and the network saw since the page was opened."""
        self.evaluate("1")  # collect the events that arrived meanwhile
        out = PageLoad()
        for ev in self._events:
            method, p = ev.get("method"), ev.get("params", {})
            if method == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                out.errors.append(f"exception: {d.get('exception', {}).get('description') or d.get('text')}")
            elif method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.errors.append("console: " + " ".join(str(a.get("value", a.get("description")))
                                                         for a in p.get("args", [])))
            elif method == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                out.errors.append(f"log: {p['entry'].get('text')}")
            elif method == "Network.requestWillBeSent":
                url = p.get("request", {}).get("url", "")
                if not url.startswith(LOCAL_SCHEMES):
                    out.requests.append(url)
        out.errors = [e for e in out.errors if not any(b in e for b in BENIGN)]
        return out

    def rect(self, selector: str) -> dict:
        """The element's box in page coordinates (CSS px)."""
        js = (f"(() => {{ const r = document.querySelector({json.dumps(selector)}).getBoundingClientRect();"
              f" return {{x: r.left + scrollX, y: r.top + scrollY, width: r.width, height: r.height}}; }})()")
        return self.evaluate(js)

    def screenshot(self, clip: dict | None = None) -> bytes:
        """PNG of a region of the page (page coordinates), or of the whole page."""
        if clip is None:
            size = self.evaluate("({w: document.documentElement.scrollWidth, h: document.documentElement.scrollHeight})")
            clip = {"x": 0, "y": 0, "width": size["w"], "height": size["h"]}
        res = self.call("Page.captureScreenshot", session=True, format="png", captureBeyondViewport=True,
                        clip=dict(clip, scale=1))
        return base64.b64decode(res["data"])

    def close(self) -> None:
        try:
            self.call("Browser.close")
        except Exception:  # noqa: BLE001 - closing anyway
            pass
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()
        for fd in (self._send, self._recv):
            os.close(fd)
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self) -> "Browser":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


# -- PNG ---------------------------------------------------------------------------------------------
def _paeth_row(raw: bytearray, prior: bytes, bpp: int) -> None:
    for i in range(len(raw)):
        a = raw[i - bpp] if i >= bpp else 0
        b = prior[i]
        c = prior[i - bpp] if i >= bpp else 0
        p = a + b - c
        pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        raw[i] = (raw[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF


def _average_row(raw: bytearray, prior: bytes, bpp: int) -> None:
    for i in range(len(raw)):
        a = raw[i - bpp] if i >= bpp else 0
        raw[i] = (raw[i] + ((a + prior[i]) >> 1)) & 0xFF


def png_pixels(data: bytes) -> np.ndarray:
    """(height, width, channels) uint8 of an 8-bit, non-interlaced RGB or RGBA PNG."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat = 8, []
    while pos < len(data):
        (n,), kind = struct.unpack(">I", data[pos:pos + 4]), data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
    if depth != 8 or color not in (2, 6) or interlace:
        raise ValueError(f"unsupported PNG (depth {depth}, color type {color}, interlace {interlace})")
    bpp = 3 if color == 2 else 4
    stream = zlib.decompress(b"".join(idat))
    stride = width * bpp
    out = np.zeros((height, stride), dtype=np.uint8)
    prior = np.zeros(stride, dtype=np.uint8)
    for y in range(height):
        kind, row = stream[y * (stride + 1)], stream[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
        cur = np.frombuffer(row, dtype=np.uint8).copy()
        if kind == 1:  # Sub: a running sum per channel
            cur = (np.cumsum(cur.reshape(width, bpp).astype(np.int64), axis=0) & 0xFF).astype(np.uint8).ravel()
        elif kind == 2:  # Up
            cur = cur + prior
        elif kind in (3, 4):
            buf = bytearray(cur.tobytes())
            (_average_row if kind == 3 else _paeth_row)(buf, prior.tobytes(), bpp)
            cur = np.frombuffer(bytes(buf), dtype=np.uint8)
        out[y] = cur
        prior = out[y]
    return out.reshape(height, width, bpp)


def distinct_colors(pixels: np.ndarray) -> int:
    rgb = pixels[..., :3].reshape(-1, 3).astype(np.uint32)
    return int(np.unique((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]).size)
