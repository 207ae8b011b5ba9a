"""Open a local HTML page in headless Chromium (Debian's ``chromium``, installed by ``.ci/run``) and read back
what a person would see: a screenshot and facts about the drawn page (its text, the tables, whether every
image decoded, any address it would fetch), through :func:`ergosim.viz.browser.capture`."""

from __future__ import annotations

from pathlib import Path

from ergosim.viz.browser import capture, chromium

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


def inspect_page(page: Path, png: Path, *, width: int = 1200, max_height: int = 6000) -> dict:
    """Load ``page`` (a file), write a screenshot of its top ``max_height`` px at ``width`` to ``png`` and
    return the facts of :data:`_FACTS` (``text``, ``tables``, ``images``, ``height``, ``external``)."""
    return capture(page.resolve().as_uri(), png, width=width, full_page=True, max_height=max_height,
                   facts=_FACTS)
