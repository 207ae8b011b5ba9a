"""Open a local HTML page in headless Chromium (Debian's ``chromium``, installed by ``.ci/run``) and read back
what a person would see: a full-page screenshot and facts about the drawn page (its text, the tables, whether
every image decoded), through the DevTools protocol on 127.0.0.1 only. The browser runs in its own process
group and is stopped at the end.
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

__all__ = ["chromium", "inspect_page"]

_FACTS = """JSON.stringify({
  text: document.body.innerText,
  tables: [...document.querySelectorAll('table')].map(t => ({rows: t.rows.length,
                                                              height: t.getBoundingClientRect().height})),
  images: [...document.images].map(i => ({complete: i.complete, width: i.naturalWidth, alt: i.alt})),
  height: document.documentElement.scrollHeight,
  external: [...document.querySelectorAll('[src],link[href]')].map(e => e.getAttribute('src') ||
                                                                    e.getAttribute('href'))
            .filter(u => /^(https?:)?\\/\\//.test(u))
})"""


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def inspect_page(page: Path, png: Path, *, width: int = 1200, max_height: int = 6000) -> dict:
    """Load ``page`` (a file), write a screenshot of its top ``max_height`` px at ``width`` to ``png`` and
    return the facts of :data:`_FACTS` (``text``, ``tables``, ``images``, ``height``, ``external``)."""
    import websockets  # noqa: PLC0415 - installed with rerun-sdk

    port = _port()
    profile = tempfile.mkdtemp(prefix="ergosim-chromium-")
    browser = subprocess.Popen([chromium(), "--headless=new", "--no-sandbox", "--disable-gpu",
                                "--no-first-run", "--no-default-browser-check", f"--user-data-dir={profile}",
                                f"--window-size={width},900", f"--remote-debugging-port={port}",
                                "--remote-debugging-address=127.0.0.1", "about:blank"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        tabs = None
        for _ in range(150):
            try:
                tabs = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json", timeout=1))
                break
            except OSError:
                time.sleep(0.2)
        ws_url = next(t for t in tabs if t["type"] == "page")["webSocketDebuggerUrl"]

        async def drive() -> dict:
            async with websockets.connect(ws_url, max_size=None) as ws:
                n = 0

                async def call(method: str, **params):
                    nonlocal n
                    n += 1
                    await ws.send(json.dumps({"id": n, "method": method, "params": params}))
                    while True:
                        m = json.loads(await ws.recv())
                        if m.get("id") == n:
                            return m.get("result", {})

                await call("Page.enable")
                await call("Page.navigate", url=page.resolve().as_uri())
                for _ in range(100):  # until the document and its images have loaded
                    done = await call("Runtime.evaluate", expression="document.readyState")
                    if done["result"]["value"] == "complete":
                        break
                    await asyncio.sleep(0.1)
                facts = json.loads((await call("Runtime.evaluate", expression=_FACTS))["result"]["value"])
                height = min(int(facts["height"]), max_height)
                await call("Emulation.setDeviceMetricsOverride", width=width, height=height,
                           deviceScaleFactor=1, mobile=False)
                shot = await call("Page.captureScreenshot", format="png")
                png.write_bytes(base64.b64decode(shot["data"]))
                return facts

        return asyncio.run(drive())
    finally:
        try:
            os.killpg(browser.pid, signal.SIGTERM)
            browser.wait(timeout=10)
        except ProcessLookupError:
            pass
        except subprocess.TimeoutExpired:
            os.killpg(browser.pid, signal.SIGKILL)
            browser.wait()
        shutil.rmtree(profile, ignore_errors=True)
