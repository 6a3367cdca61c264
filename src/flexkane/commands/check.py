"""``flexkane check``: validate a model without running it."""

from __future__ import annotations

from ._common import add_model_arguments, model_from_args

__all__ = ["register"]


def register(subparsers) -> None:
    p = subparsers.add_parser("check", help="validate a model file without running it",
                              description="Check every field and reference of a model; exit 0 if valid, "
                                          "2 with a message naming the field otherwise.")
    add_model_arguments(p, default=None)
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from ..kane.chain import build_chain

    model = model_from_args(args)
    chain = build_chain(model)   # also checks initial conditions against the coordinates
    print(f"{args.model}: valid ({len(model.bodies)} bodies, {len(model.beams)} beams, "
          f"{len(model.joints)} joints, {len(chain.coordinates)} generalized coordinates: "
          f"{', '.join(c.q.name for c in chain.coordinates)})")
    return 0
