"""Movie files from RGB frames: GIF through Pillow, MP4 through the ffmpeg of imageio-ffmpeg.

imageio-ffmpeg (a PyPI package) ships a static ffmpeg executable, and uses ``$IMAGEIO_FFMPEG_EXE``
or an ffmpeg on ``PATH`` where it has none for the platform. Without it the MP4 is skipped with
:data:`MP4_MISSING`.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np

__all__ = ["ffmpeg_executable", "MP4_MISSING", "GifWriter", "Mp4Writer"]

#: Message shown when no MP4 can be written.
MP4_MISSING = ("MP4 skipped: no ffmpeg found; install the extra flexkane[video] "
               "(pip install 'flexkane[video]', or pip install imageio-ffmpeg) to get one. The GIF is written.")


def ffmpeg_executable() -> str | None:
    """Path of the ffmpeg executable imageio-ffmpeg provides, or None."""
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    with contextlib.suppress(Exception):   # no binary for this platform and none on PATH
        exe = imageio_ffmpeg.get_ffmpeg_exe()
        if exe and Path(exe).exists():
            return str(exe)
    return None


class GifWriter:
    """Collects frames and writes a looping GIF with Pillow.

    Parameters
    ----------
    path : pathlib.Path
        File to write (its name must end in ``.gif``).
    fps : float
        Frames per second [1/s].
    reference : ndarray, shape (height, width, 3), uint8
        A frame holding every colour of the movie (the last one: the whole trace is drawn); its
        palette of 128 colours serves every frame, which keeps the colours steady and is fast.
    """

    def __init__(self, path: Path, fps: float, reference: np.ndarray):
        from PIL import Image

        self.path = Path(path)
        self.duration = max(int(round(1000.0 / fps)), 20)     # [ms]; browsers slow faster GIFs down
        self.palette = Image.fromarray(reference).quantize(colors=128, method=Image.Quantize.MEDIANCUT)
        self.frames = []

    def add(self, rgb: np.ndarray) -> None:
        """Append a frame, shape (height, width, 3), uint8."""
        from PIL import Image

        self.frames.append(Image.fromarray(rgb).quantize(palette=self.palette, dither=Image.Dither.NONE))

    def close(self) -> None:
        """Write the file."""
        first, rest = self.frames[0], self.frames[1:]
        first.save(self.path, format="GIF", save_all=True, append_images=rest, duration=self.duration,
                   loop=0, optimize=False, disposal=1)


class Mp4Writer:
    """Streams frames to ffmpeg (H.264, yuv420p, playable in browsers).

    Parameters
    ----------
    path : pathlib.Path
        File to write (``.mp4``).
    fps : float
        Frames per second [1/s].
    size : (int, int)
        Width and height [pixels], both even.
    """

    def __init__(self, path: Path, fps: float, size: tuple[int, int]):
        import imageio_ffmpeg

        self.path = Path(path)
        self._gen = imageio_ffmpeg.write_frames(str(path), size, fps=fps, codec="libx264",
                                                pix_fmt_out="yuv420p", quality=7, macro_block_size=2,
                                                ffmpeg_log_level="error", output_params=["-y"])
        self._gen.send(None)

    def add(self, rgb: np.ndarray) -> None:
        """Append a frame, shape (height, width, 3), uint8."""
        self._gen.send(np.ascontiguousarray(rgb))

    def close(self) -> None:
        """Finish the file (waits for ffmpeg)."""
        self._gen.close()
