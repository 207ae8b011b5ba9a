"""Screenshot a rerun recording as a person sees it: rerun's web viewer in headless Chromium.

    python scripts/rrd_snapshot.py RUN.rrd OUT.png [--wait 60] [--size 1600x1000]

Needs Debian's ``chromium`` (``apt-get install -y chromium``; ``.ci/run`` installs it). The viewer serves
on 127.0.0.1 only and is stopped at the end, with the browser (:func:`ergosim.viz.browser.capture`). The
software rasteriser is slow: a large recording may need ``--wait 90``. Open OUT.png and look at it.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
import urllib.parse
import urllib.request
from pathlib import Path

from ergosim.viz.browser import capture, free_port, stop_group


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rrd", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--wait", type=float, default=60.0, help="seconds to let the viewer load and draw")
    ap.add_argument("--size", default="1600x1000", help="the window, WxH pixels")
    a = ap.parse_args()
    width, height = (int(x) for x in a.size.split("x"))
    rerun = Path(sys.executable).with_name("rerun")
    rerun = str(rerun) if rerun.exists() else shutil.which("rerun")
    if not rerun:
        sys.exit("no rerun CLI next to this python: run this with the project's venv python")
    web, grpc = free_port(), free_port()
    viewer = subprocess.Popen([rerun, "--serve-web", "--bind", "127.0.0.1", "--web-viewer-port", str(web),
                               "--port", str(grpc), str(a.rrd)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        for _ in range(100):
            try:
                urllib.request.urlopen(f"http://127.0.0.1:{web}/", timeout=1)
                break
            except OSError:
                time.sleep(0.2)
        source = urllib.parse.quote(f"rerun+http://127.0.0.1:{grpc}/proxy", safe="")
        capture(f"http://127.0.0.1:{web}/?url={source}", a.out, width=width, height=height, wait=a.wait,
                gpu=True)
        print(f"wrote {a.out}")
        return 0
    finally:
        stop_group(viewer)


if __name__ == "__main__":
    raise SystemExit(main())
