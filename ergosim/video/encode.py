"""MP4 and GIF files through imageio-ffmpeg's ffmpeg (H.264, yuv420p: plays in every browser and player).

Both are written like every other output: into a temporary file beside the target, renamed over it only
when the encoder finished, so a file under the final name is always whole.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from ergosim.atomic import check_output_file
from ergosim.errors import RenderError

__all__ = ["Mp4Writer", "ffmpeg_exe", "gif_from_mp4", "read_mp4"]


def ffmpeg_exe() -> str:
    """The ffmpeg binary that ships with imageio-ffmpeg (nothing is downloaded)."""
    try:
        import imageio_ffmpeg  # noqa: PLC0415 - only videos need it

        return imageio_ffmpeg.get_ffmpeg_exe()
    except (ImportError, RuntimeError) as err:
        raise RenderError(f"no video encoder: {err}; install ergosim with its dependencies "
                          "(pip install -e .), which include imageio-ffmpeg", where="--video") from None


def _temp_beside(target: Path, suffix: str) -> Path:
    check_output_file(target, where=str(target))
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=f".tmp{suffix}", dir=target.parent)
    os.close(fd)
    return Path(tmp)


class Mp4Writer:
    """``with Mp4Writer(path, width, height, fps=30) as w: w.write(frame)`` for (height, width, 3) uint8
    frames; ``crf`` is x264's constant rate factor (lower is better and larger; 23 is x264's default)."""

    def __init__(self, path: str | os.PathLike[str], width: int, height: int, *, fps: float = 30.0,
                 crf: int = 23) -> None:
        if width % 2 or height % 2:
            raise RenderError(f"video size must be even for H.264 yuv420p, got {width}x{height}",
                              where="--video-size")
        import imageio_ffmpeg  # noqa: PLC0415

        ffmpeg_exe()
        self.path = Path(path)
        self.width, self.height, self.fps = width, height, fps
        self.frames = 0
        self._tmp = _temp_beside(self.path, ".mp4")
        self._gen = imageio_ffmpeg.write_frames(
            str(self._tmp), (width, height), fps=fps, codec="libx264", quality=None, macro_block_size=2,
            ffmpeg_log_level="error", output_params=["-crf", str(crf), "-preset", "veryfast",
                                                     "-movflags", "+faststart"])
        self._gen.send(None)

    def write(self, frame: np.ndarray) -> None:
        if frame.shape != (self.height, self.width, 3) or frame.dtype != np.uint8:
            raise ValueError(f"frame must be ({self.height}, {self.width}, 3) uint8, got {frame.shape} "
                             f"{frame.dtype}")
        self._gen.send(np.ascontiguousarray(frame))
        self.frames += 1

    def close(self, commit: bool = True) -> None:
        gen, self._gen = self._gen, None
        if gen is None:
            return
        try:
            gen.close()
            if commit:
                os.chmod(self._tmp, 0o666 & ~_umask())
                os.replace(self._tmp, self.path)
        finally:
            with contextlib.suppress(FileNotFoundError):
                self._tmp.unlink()

    def __enter__(self) -> Mp4Writer:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(commit=exc_type is None)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def read_mp4(path: str | os.PathLike[str]) -> tuple[dict, list[np.ndarray]]:
    """(metadata, frames (height, width, 3) uint8) of a video file, decoded by the same ffmpeg."""
    import imageio_ffmpeg  # noqa: PLC0415

    gen = imageio_ffmpeg.read_frames(str(path))
    meta = gen.__next__()
    w, h = meta["size"]
    frames = [np.frombuffer(b, dtype=np.uint8).reshape(h, w, 3) for b in gen]
    return meta, frames


def gif_from_mp4(mp4: str | os.PathLike[str], gif: str | os.PathLike[str], *, width: int = 480,
                 fps: float = 10.0, colors: int = 128) -> Path:
    """A looping GIF of ``mp4`` scaled to ``width`` px at ``fps``, with one palette made for the whole clip
    (ffmpeg's palettegen/paletteuse), written atomically. Returns the GIF's path."""
    target = Path(gif)
    tmp = _temp_beside(target, ".gif")
    graph = (f"fps={fps:g},scale={width}:-2:flags=lanczos,split[a][b];"
             f"[a]palettegen=max_colors={colors}:stats_mode=diff[p];"
             "[b][p]paletteuse=dither=bayer:bayer_scale=4:diff_mode=rectangle")
    cmd = [ffmpeg_exe(), "-y", "-loglevel", "error", "-i", str(mp4), "-vf", graph, "-loop", "0", str(tmp)]
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise RenderError(f"ffmpeg could not make the GIF: {' '.join(done.stderr.split())[:300]}",
                              where=str(target))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
    return target
