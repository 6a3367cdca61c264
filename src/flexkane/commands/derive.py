"""``flexkane derive``: print F*_r and F_r of a model in the chapter's notation."""

from __future__ import annotations

import sys
import time

from ._common import add_model_arguments, model_from_args

__all__ = ["add_no_cache_argument", "register"]


def add_no_cache_argument(parser) -> None:
    """``--no-cache``: derive the equations afresh instead of loading them from the cache."""
    parser.add_argument("--no-cache", action="store_true",
                        help="derive the equations afresh instead of loading them from the cache of derived "
                             "equations (and store nothing there)")


def register(subparsers) -> None:
    p = subparsers.add_parser("derive", help="print the generalized inertia and active forces",
                              description="Derive Kane's equations and print F*_r (eq. 8.22) and F_r by "
                                          "source (eqs. 8.28-8.35) for every generalized speed; a spatial "
                                          "model's are the spatial generalization of those planar equations.")
    add_model_arguments(p)
    p.add_argument("--latex", action="store_true", help="print LaTeX instead of text")
    p.add_argument("--markdown", action="store_true", help="print the whole Markdown report (equations.md)")
    add_no_cache_argument(p)
    p.add_argument("--quiet", action="store_true", help="print the equations only (no progress, no timing)")
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from ..derivation_cache import Derivation, derive

    model = model_from_args(args)
    start = time.perf_counter()
    derived = []
    eom = derive(model, cache=not args.no_cache, announce=lambda: derived.append(True))
    elapsed = time.perf_counter() - start
    derivation = Derivation(eom=eom, cache=not args.no_cache)   # the printed text rendered once per structure
    if args.markdown:
        print(derivation.equations(model)["md"])
    else:
        print(derivation.forces_text(latex=args.latex))
    how = "derived" if derived else "loaded from the cache"
    if not args.quiet:
        print(f"# {how} {len(eom.all_speeds)} equations in {elapsed:.3f} s", file=sys.stderr)
    return 0
