"""Animations as GIF (always, through imageio/Pillow) and MP4 (when an ffmpeg from a wheel,
``imageio-ffmpeg``, is installed)."""

from __future__ import annotations

import contextlib
import os
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from bristlecrawler.io.atomic import atomic_path


@contextlib.contextmanager
def _fork_ok():
    """Silence JAX's warning about os.fork() for a subprocess that execs at once (ffmpeg)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r"os\.fork\(\) was called")
        yield


def _render(fig) -> np.ndarray:
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def mp4_available() -> bool:
    try:
        import imageio_ffmpeg  # noqa: F401
    except ImportError:
        return False
    return True


def write_animation(
    draw: Callable[[object, int], None],
    n_frames: int,
    path_stem: str | os.PathLike,
    fps: float = 10.0,
    figsize: tuple[float, float] = (8.0, 3.0),
    dpi: int = 90,
) -> list[Path]:
    """Render ``draw(ax, i)`` for i in range(n_frames) and write ``<stem>.gif`` (and
    ``<stem>.mp4`` when possible). Returns the written paths."""
    import imageio.v3 as iio

    from bristlecrawler.viz.reduced import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    frames = []
    for i in range(n_frames):
        ax.clear()
        draw(ax, i)
        frames.append(_render(fig))
    plt.close(fig)
    stem = Path(path_stem)
    written = []
    with atomic_path(stem.with_suffix(".gif")) as tmp:
        iio.imwrite(tmp, frames, extension=".gif", duration=1000.0 / fps, loop=0)
    written.append(stem.with_suffix(".gif"))
    if mp4_available():
        # Codecs want sizes in 16-pixel blocks: pad with white (imageio would rescale, and
        # say so on stderr).
        h, w = frames[0].shape[:2]
        pad = ((0, -h % 16), (0, -w % 16), (0, 0))
        padded = [np.pad(f, pad, constant_values=255) for f in frames]
        with atomic_path(stem.with_suffix(".mp4")) as tmp, _fork_ok():
            iio.imwrite(tmp, padded, extension=".mp4", fps=fps, codec="libx264")
        written.append(stem.with_suffix(".mp4"))
    return written
