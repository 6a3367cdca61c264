"""``flexkane animate RUN_DIR``: a GIF (and an MP4 where ffmpeg exists) of a finished run."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import ModelError

__all__ = ["register", "add_animation_arguments", "animate_run"]


def add_animation_arguments(parser, *, movie_options: bool = True) -> None:
    """``--magnify``, ``--trace`` and ``--view`` (shared with ``run``); ``--fps``, ``--frames``, ``--no-mp4``."""
    parser.add_argument("--magnify", default="1", metavar="K",
                        help="magnification of the beam displacements, a number or 'auto' (a round factor "
                             "that draws the largest one at about a tenth of the beam) [default: 1]")
    parser.add_argument("--trace", default=None, metavar="POINT",
                        help="point whose path is drawn: a body (its mass centre), a beam (its tip), 'cm' "
                             "(centre of mass of the system) or 'none' [default: the tip of the last beam]")
    parser.add_argument("--view", default=None, metavar="ELEV,AZIM",
                        help="spatial models (dimensions = 3): elevation and azimuth of the camera [deg]; "
                             "90,-90 looks down the z axis with x to the right [default: 25,-60]")
    if not movie_options:
        return
    parser.add_argument("--fps", type=float, default=20.0, metavar="N", help="frames per second [default: 20]")
    parser.add_argument("--frames", type=int, default=120, metavar="N",
                        help="largest number of frames, evenly spread over the run [default: 120]")
    parser.add_argument("--no-mp4", action="store_true", help="write the GIF only")


def register(subparsers) -> None:
    p = subparsers.add_parser("animate", help="animate a finished run (GIF, and MP4 where ffmpeg exists)",
                              description="Draw the chain of a finished run at its output times: rigid bodies "
                                          "as outlines, beams as deformed centre lines, the time and the path "
                                          "of a point on every frame. Reads RUN_DIR/results.npz only.")
    p.add_argument("run_dir", metavar="RUN_DIR", help="directory of a run (holds results.npz)")
    add_animation_arguments(p)
    p.add_argument("--out", metavar="FILE", default=None,
                   help="GIF to write; the MP4 goes beside it [default: RUN_DIR/animation.gif]")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary")
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    run_dir = Path(args.run_dir)
    npz = run_dir / "results.npz" if run_dir.is_dir() else run_dir
    if not npz.is_file():
        raise ModelError("RUN_DIR", "a run directory holding results.npz", str(args.run_dir))
    from ..results import load_results

    results = load_results(npz)
    out = Path(args.out) if args.out else npz.parent / "animation.gif"
    animate_run(results, out, args, quiet=args.quiet)
    return 0


def animate_run(results, out: Path, args, *, quiet: bool) -> list[Path]:
    """Animate ``results`` into ``out`` with the options of :func:`add_animation_arguments`."""
    from ..animation import animate
    from ..progress import activity

    if out.parent and not out.parent.is_dir():
        raise ModelError("--out", "a file in an existing directory", str(out))
    fps = getattr(args, "fps", 20.0)
    frames = getattr(args, "frames", 120)
    with activity(f"drawing the animation {out.name}", delay=1.0, thread=False) as bar:   # on stderr (--quiet: not)
        movie = animate(results, out, magnify=args.magnify, trace=args.trace, fps=fps, frames=frames,
                        mp4=not getattr(args, "no_mp4", False), progress=lambda k, n: bar.update(k, n, "frames"),
                        view=getattr(args, "view", None))
    for message in movie.messages:
        print(f"flexkane: {message}", file=sys.stderr)
    written = [movie.gif] + ([movie.mp4] if movie.mp4 else [])
    if not quiet:
        magnified = "" if movie.magnify is None else f", beam deflection x {movie.magnify:g}"
        print(f"animation: {movie.frames} frames{magnified}, trace {movie.trace}; "
              f"wrote {', '.join(str(p) for p in written)}")
    return written
