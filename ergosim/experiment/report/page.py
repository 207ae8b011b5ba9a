"""The HTML of report.html: one self-contained page, no network (inline CSS, images as data URIs).

Small builders that return HTML text with every value escaped; :mod:`~ergosim.experiment.report.sections`
says what the page holds.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Sequence
from pathlib import Path

__all__ = ["esc", "page", "section", "para", "table", "image", "data_uri", "details"]

_CSS = """
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;color:#1d2330;margin:0;
background:#f4f5f7}
main{max-width:1100px;margin:0 auto;padding:24px 28px 60px;background:#fff}
h1{font-size:26px;margin:0 0 4px}
h2{font-size:20px;margin:32px 0 8px;border-bottom:2px solid #dde1e8;padding-bottom:4px}
h3{font-size:16px;margin:18px 0 6px}
p{margin:6px 0 10px}
.meta{color:#586174;font-size:14px}
table{border-collapse:collapse;margin:8px 0 14px;font-size:14px}
th,td{border:1px solid #d5d9e0;padding:4px 8px;text-align:left;vertical-align:top}
th{background:#eef1f5;font-weight:600}
td.n{text-align:right;font-variant-numeric:tabular-nums}
td.H{background:#dbe9fb;text-align:center}
td.R{background:#fbdcdc;text-align:center}
td.x{background:#f3e3c3;text-align:center}
td.d{text-align:center;color:#8a93a3}
figure{margin:10px 0 18px}
figure img{max-width:100%;border:1px solid #dde1e8}
figcaption{font-size:13px;color:#586174}
.note{background:#fff7e0;border-left:4px solid #e6b23a;padding:6px 10px}
.ok{background:#e7f6ea;border-left:4px solid #3aa35a;padding:6px 10px}
details{margin:4px 0}
summary{cursor:pointer;font-weight:600}
code{background:#f0f2f5;padding:0 3px}
"""


def esc(value: object) -> str:
    return html.escape(str(value), quote=True)


def page(title: str, body: Iterable[str]) -> str:
    """The whole document: ``title`` and the ``body`` parts in order."""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{esc(title)}</title><style>{_CSS}</style></head>\n<body><main>\n"
            + "\n".join(body) + "\n</main></body></html>\n")


def section(title: str, parts: Iterable[str], anchor: str) -> str:
    return f"<section id=\"{esc(anchor)}\"><h2>{esc(title)}</h2>\n" + "\n".join(parts) + "\n</section>"


def para(text: str, cls: str = "") -> str:
    """A paragraph of plain ``text`` (escaped); ``cls`` ``note`` or ``ok`` frames it."""
    return f"<p class=\"{cls}\">{esc(text)}</p>" if cls else f"<p>{esc(text)}</p>"


def table(header: Sequence[str], rows: Iterable[Sequence[object]], *, classes: Sequence[str] = (),
          cell_class=None, cls: str = "") -> str:
    """A table; ``classes``: a CSS class per column (``n``: a number, right-aligned); ``cell_class(text)``:
    a class for a body cell from its text (the allocation marks)."""
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = []
    for row in rows:
        cells = []
        for k, value in enumerate(row):
            c = cell_class(str(value)) if cell_class else (classes[k] if k < len(classes) else "")
            cells.append(f"<td class=\"{c}\">{esc(value)}</td>" if c else f"<td>{esc(value)}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    attr = f" class=\"{cls}\"" if cls else ""
    return f"<table{attr}><thead><tr>{head}</tr></thead><tbody>\n" + "\n".join(body) + "\n</tbody></table>"


def data_uri(path: Path, mime: str) -> str:
    return f"data:{mime};base64," + base64.b64encode(path.read_bytes()).decode("ascii")


def image(path: Path, caption: str, alt: str) -> str:
    """A PNG of the run folder inlined as a data URI, with its caption."""
    return (f"<figure><img src=\"{data_uri(path, 'image/png')}\" alt=\"{esc(alt)}\">"
            f"<figcaption>{esc(caption)}</figcaption></figure>")


def details(title: str, inner: str, *, open_: bool = False) -> str:
    return f"<details{' open' if open_ else ''}><summary>{esc(title)}</summary>\n{inner}\n</details>"
