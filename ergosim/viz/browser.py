"""Pages as a person sees them: headless Chromium (Debian's ``chromium`` package), driven over its DevTools
protocol on 127.0.0.1 only, loads a page, reads facts from it and takes a screenshot. Used to check that
report.html draws whole (tests/test_report.py) and to take the docs' screenshots of report.html and of
rerun's web viewer (``scripts/rrd_snapshot.py``). The browser runs in its own process group with its own
profile, and is stopped at the end.
"""

from __future__ import annotations

import asyncio
import base64
import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path

from ergosim.errors import RenderError

__all__ = ["chromium", "free_port", "capture", "stop_group"]


def chromium() -> str | None:
    """The Chromium executable on PATH, or None (``apt-get install -y chromium``)."""
    return shutil.which("chromium") or shutil.which("chromium-browser")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_json(url: str, tries: int = 150):
    for _ in range(tries):
        try:
            return json.load(urllib.request.urlopen(url, timeout=1))
        except OSError:
            time.sleep(0.2)
    raise RenderError(f"no answer from {url}", where="chromium")


def capture(url: str, png: Path, *, width: int = 1200, height: int = 900, full_page: bool = False,
            max_height: int = 6000, wait: float = 0.0, facts: str | None = None, gpu: bool = False) -> dict:
    """Load ``url``, let it draw for ``wait`` s after the document is complete, evaluate the JavaScript
    expression ``facts`` (it returns a JSON string; the dict is returned, else {}), and write a screenshot of
    ``width`` × ``height`` px (``full_page``: the page's height, at most ``max_height``) to ``png``. ``gpu``
    gives WebGL a software rasteriser (SwiftShader), which rerun's viewer needs."""
    import websockets  # noqa: PLC0415 - installed with rerun-sdk; only where a page is captured

    exe = chromium()
    if exe is None:
        raise RenderError("no chromium on PATH: apt-get update && apt-get install -y chromium",
                          where="chromium")
    port = free_port()
    profile = tempfile.mkdtemp(prefix="ergosim-chromium-")
    flags = (["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"] if gpu
             else ["--disable-gpu"])
    browser = subprocess.Popen([exe, "--headless=new", "--no-sandbox", "--no-first-run",
                                "--no-default-browser-check", f"--user-data-dir={profile}", *flags,
                                f"--window-size={width},{height}", f"--remote-debugging-port={port}",
                                "--remote-debugging-address=127.0.0.1", "about:blank"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        tabs = _wait_json(f"http://127.0.0.1:{port}/json")
        ws_url = next(t for t in tabs if t["type"] == "page")["webSocketDebuggerUrl"]
        return asyncio.run(_drive(websockets, ws_url, url, png, width, height, full_page, max_height, wait,
                                  facts))
    finally:
        stop_group(browser)
        shutil.rmtree(profile, ignore_errors=True)


def stop_group(proc: subprocess.Popen) -> None:
    """Stop ``proc``, started with ``start_new_session=True``, and its children: SIGTERM to its process
    group, SIGKILL after 10 s."""
    try:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=10)
    except ProcessLookupError:
        pass
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


async def _drive(websockets, ws_url, url, png, width, height, full_page, max_height, wait, facts) -> dict:
    async with websockets.connect(ws_url, max_size=None) as ws:
        n = 0

        async def call(method: str, **params) -> dict:
            nonlocal n
            n += 1
            await ws.send(json.dumps({"id": n, "method": method, "params": params}))
            while True:
                m = json.loads(await ws.recv())
                if m.get("id") == n:
                    return m.get("result", {})

        async def value(expression: str):
            return (await call("Runtime.evaluate", expression=expression))["result"].get("value")

        await call("Page.enable")
        await call("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1,
                   mobile=False)
        await call("Page.navigate", url=url)
        for _ in range(100):  # until the document and its images have loaded
            if await value("document.readyState") == "complete":
                break
            await asyncio.sleep(0.1)
        await asyncio.sleep(wait)
        found = json.loads(await value(facts)) if facts else {}
        if full_page:
            tall = min(int(await value("document.documentElement.scrollHeight")), max_height)
            await call("Emulation.setDeviceMetricsOverride", width=width, height=tall, deviceScaleFactor=1,
                       mobile=False)
        shot = await call("Page.captureScreenshot", format="png")
        Path(png).write_bytes(base64.b64decode(shot["data"]))
        return found
