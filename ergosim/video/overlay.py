"""The overlay drawn on each video frame (Pillow; fonts from matplotlib's bundled DejaVu Sans).

::

    +------------------------------------+                      +----------------------------+
    | multi-subject · subject 0 · hrc    |                      | KWear V          | V_th 0.80|
    | t 62.4 s     repetition 2/3    ×4  |                      | shoulder ██████░░|░░  0.61  |
    | [ROBOT] a2  insert L               |                      | elbow    ████░░░░|░░  0.42  |
    +------------------------------------+                      | ...                        |
                                                                +----------------------------+
    +------------------------------------------------------------------------------------------+
    | t 61.9 s  a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.80; cost robot 2.50 < ...   |
    +------------------------------------------------------------------------------------------+

Top left: the simulated time, the repetition, the speed-up, and the attempt in progress with its agent
(blue the worker, red a robot, the colours of the rerun recording and the plots). Top right: KWear V per
joint as bars from 0 to 1 in the joints' plot colours, with V_th marked; a value at or above V_th turns
orange. Bottom: each allocation's one-line reason as the allocator wrote it, and failures (orange), for
a few seconds of video after they happen. Sizes scale with the frame height (reference 540 px).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ergosim.colors import JOINT_COLORS, agent_color
from ergosim.posture import KWEAR_JOINTS
from ergosim.video.timeline import FrameInfo

__all__ = ["Overlay", "WARN_COLOR"]

WARN_COLOR = (230, 126, 34)
"""Orange: failures, and a joint at or above V_th (the recording's colour for failures)."""
_PANEL = (16, 18, 24, 178)
_TEXT = (240, 240, 240)
_MUTED = (170, 175, 185)
_TRACK = (70, 74, 84)


def _font(size: int, bold: bool = False) -> ImageFont.FreeTypeFont:
    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    return ImageFont.truetype(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name), size)


class Overlay:
    """Draws :class:`FrameInfo` onto (height, width, 3) uint8 frames. ``header``: the first line (scenario,
    subject, mode); ``speed``: the video's speed-up, shown when it is not 1; ``text_scale``: the overlay's
    size against the frame (1: 19 px time line at 540 px; larger for small frames, e.g. a GIF)."""

    def __init__(self, width: int, height: int, *, header: str = "", speed: float = 1.0,
                 text_scale: float = 1.0) -> None:
        self.width, self.height = width, height
        s = height / 540 * text_scale
        self.s = s
        self.header = header
        self.speed = speed
        self.f_small = _font(max(9, round(12 * s)))
        self.f_main = _font(max(11, round(19 * s)), bold=True)
        self.f_text = _font(max(10, round(15 * s)))
        self.f_bold = _font(max(10, round(15 * s)), bold=True)
        self.f_event = _font(max(9, round(13 * s)))
        self.pad = round(10 * s)
        self.margin = round(12 * s)

    # -- panels ---------------------------------------------------------------------------------------------
    def draw(self, frame: np.ndarray, info: FrameInfo) -> np.ndarray:
        """A new (height, width, 3) uint8 frame: ``frame`` with the overlay."""
        if frame.shape != (self.height, self.width, 3):
            raise ValueError(f"frame must be ({self.height}, {self.width}, 3), got {frame.shape}")
        base = Image.fromarray(frame).convert("RGBA")
        layer = Image.new("RGBA", base.size, (0, 0, 0, 0))
        shade = ImageDraw.Draw(layer)
        text_ops: list = []
        self._status(shade, text_ops, info)
        self._bars(shade, text_ops, info)
        self._events(shade, text_ops, info)
        img = Image.alpha_composite(base, layer)
        draw = ImageDraw.Draw(img)
        for op in text_ops:
            op(draw)
        return np.asarray(img.convert("RGB"))

    def _status(self, shade: ImageDraw.ImageDraw, ops: list, info: FrameInfo) -> None:
        s, pad, x0, y0 = self.s, self.pad, self.margin, self.margin
        chip = info.agent.upper()
        label = f"{info.action}  {info.action_text}".rstrip()
        measure = ImageDraw.Draw(Image.new("RGB", (1, 1)))
        action_w = (measure.textlength(chip, font=self.f_bold) + measure.textlength(label, font=self.f_bold)
                    + round(18 * s)) if info.action else 0
        others = [(a, g, f"{a}  {t}".rstrip()) for a, g, t in info.also]
        for _, g, text in others:
            wide = measure.textlength(g.upper(), font=self.f_bold) + measure.textlength(text,
                                                                                         font=self.f_bold)
            action_w = max(action_w, wide + round(18 * s))
        header_w = measure.textlength(self.header, font=self.f_small)
        w = max(round(340 * s), round(action_w) + 2 * pad, round(header_w) + 2 * pad)
        lines_h = [self.f_small.size + round(6 * s), self.f_main.size + round(8 * s), self.f_text.size + 4]
        step = self.f_bold.size + round(10 * s)
        h = pad * 2 + sum(lines_h) + step * len(others)
        shade.rounded_rectangle((x0, y0, x0 + w, y0 + h), radius=round(6 * s), fill=_PANEL)
        x, y = x0 + pad, y0 + pad
        header = self.header
        ops.append(lambda d, y=y: d.text((x, y), header, font=self.f_small, fill=_MUTED))
        y += lines_h[0]
        rep = f"repetition {info.repetition}/{info.repetitions}"
        speed = "" if abs(self.speed - 1.0) < 1e-9 else f"×{self.speed:g}"
        time_text = f"t {info.time:6.1f} s"

        def main_line(d, y=y):
            d.text((x, y), time_text, font=self.f_main, fill=_TEXT)
            d.text((x + round(128 * s), y), rep, font=self.f_main, fill=_TEXT)
            if speed:
                d.text((x0 + w - pad - d.textlength(speed, font=self.f_main), y), speed, font=self.f_main,
                       fill=_MUTED)
        ops.append(main_line)
        y += lines_h[1]
        if info.action:
            # every attempt in progress, one chip each (several at once in parallel execution)
            for k, (agent, text) in enumerate([(info.agent, label)] + [(g, t) for _, g, t in others]):
                color = agent_color(agent)

                def action_line(d, y=y + k * step, chip=agent.upper(), text=text, color=color):
                    cw = d.textlength(chip, font=self.f_bold) + round(10 * s)
                    d.rounded_rectangle((x, y - 1, x + cw, y + self.f_bold.size + round(4 * s)),
                                        radius=round(4 * s), fill=color)
                    d.text((x + round(5 * s), y), chip, font=self.f_bold, fill=(255, 255, 255))
                    d.text((x + cw + round(8 * s), y), text, font=self.f_bold, fill=_TEXT)
                ops.append(action_line)
        else:
            ops.append(lambda d, y=y: d.text((x, y), "no action in progress", font=self.f_text, fill=_MUTED))

    def _bars(self, shade: ImageDraw.ImageDraw, ops: list, info: FrameInfo) -> None:
        s, pad = self.s, self.pad
        label_w, bar_w, value_w = round(64 * s), round(130 * s), round(40 * s)
        row = round(20 * s)
        w = pad * 2 + label_w + bar_w + value_w
        x0 = self.width - self.margin - w
        y0 = self.margin
        title_h = self.f_small.size + round(8 * s)
        h = pad * 2 + title_h + row * len(KWEAR_JOINTS)
        shade.rounded_rectangle((x0, y0, x0 + w, y0 + h), radius=round(6 * s), fill=_PANEL)
        bx = x0 + pad + label_w
        th_x = bx + round(bar_w * min(max(info.v_th, 0.0), 1.0))
        ops.append(lambda d: d.text((x0 + pad, y0 + pad), "KWear V per joint", font=self.f_small,
                                    fill=_MUTED))
        th_label = f"V_th {info.v_th:.2f}"
        ops.append(lambda d: d.text((th_x - d.textlength(th_label, font=self.f_small) / 2, y0 + pad),
                                    th_label, font=self.f_small, fill=_TEXT))
        bar_h = round(11 * s)
        for j, joint in enumerate(KWEAR_JOINTS):
            y = y0 + pad + title_h + j * row
            v = float(info.kwear[j])
            over = v >= info.v_th
            by = y + (row - bar_h) // 2 - round(2 * s)
            fill_x = bx + round(bar_w * min(max(v, 0.0), 1.0))

            def bar(d, y=y, by=by, fill_x=fill_x, joint=joint, v=v, over=over):
                d.text((x0 + pad, y), joint, font=self.f_small, fill=_TEXT)
                d.rectangle((bx, by, bx + bar_w, by + bar_h), fill=_TRACK)
                if fill_x > bx:
                    d.rectangle((bx, by, fill_x, by + bar_h), fill=JOINT_COLORS[joint])
                d.line((th_x, by - round(3 * s), th_x, by + bar_h + round(3 * s)), fill=(255, 255, 255),
                       width=max(1, round(2 * s)))
                d.text((bx + bar_w + round(6 * s), y), f"{v:.2f}", font=self.f_bold if over else self.f_small,
                       fill=WARN_COLOR if over else _TEXT)
            ops.append(bar)

    def _events(self, shade: ImageDraw.ImageDraw, ops: list, info: FrameInfo) -> None:
        if not info.events:
            return
        s, pad = self.s, self.pad
        x0, x1 = self.margin, self.width - self.margin
        stamp_w = round(62 * s)
        text_w = x1 - x0 - 2 * pad - stamp_w - round(8 * s)
        measure = ImageDraw.Draw(Image.new("RGB", (1, 1)))
        blocks = [(e, _wrap(measure, e.text, self.f_event, text_w, 2)) for e in info.events]
        line_h = self.f_event.size + round(5 * s)
        h = pad * 2 + line_h * sum(len(lines) for _, lines in blocks)
        y0 = self.height - self.margin - h
        shade.rounded_rectangle((x0, y0, x1, y0 + h), radius=round(6 * s), fill=_PANEL)
        y = y0 + pad
        for e, lines in blocks:
            accent = WARN_COLOR if e.kind == "failure" else agent_color(e.agent)
            top = y

            def event(d, e=e, lines=lines, top=top, accent=accent):
                bottom = top + line_h * len(lines) - round(4 * s)
                d.rectangle((x0 + round(3 * s), top, x0 + round(6 * s), bottom), fill=accent)
                d.text((x0 + pad, top), f"t {e.time:.1f} s", font=self.f_small, fill=_MUTED)
                for k, line in enumerate(lines):
                    d.text((x0 + pad + stamp_w, top + k * line_h), line, font=self.f_event,
                           fill=WARN_COLOR if e.kind == "failure" else _TEXT)
            ops.append(event)
            y += line_h * len(lines)


def _wrap(draw: ImageDraw.ImageDraw, text: str, font, width: int, max_lines: int) -> list[str]:
    """``text`` broken at spaces into at most ``max_lines`` lines of at most ``width`` px (the last one cut
    with an ellipsis)."""
    lines: list[str] = []
    line = ""
    for word in text.split():
        trial = f"{line} {word}".strip()
        if draw.textlength(trial, font=font) <= width or not line:
            line = trial
        else:
            lines.append(line)
            line = word
    lines.append(line)
    if len(lines) > max_lines:
        lines = lines[:max_lines]
        last = lines[-1]
        while last and draw.textlength(last + " …", font=font) > width:
            last = last[:-1]
        lines[-1] = last.rstrip() + " …"
    return lines
