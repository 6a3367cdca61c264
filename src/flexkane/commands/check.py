"""``flexkane check``: validate a model without deriving or running it."""

from __future__ import annotations

import sys

from ._common import add_model_arguments, model_from_args

__all__ = ["register"]


def register(subparsers) -> None:
    p = subparsers.add_parser("check", help="validate a model file without running it",
                              description="Check every field, reference and the chain of a model (types, "
                                          "ranges with units, names, the joint tree, shape families, "
                                          "coordinates and initial conditions) without deriving the "
                                          "equations; exit 0 if valid, 2 with a message naming the field "
                                          "otherwise.")
    add_model_arguments(p, default=None)
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from ..model.coordinates import coordinate_names

    model = model_from_args(args)   # validates fields, references, shape families and the chain
    sweep = _check_sweep_table(args.model, model)
    coordinates = coordinate_names(model)
    if model.dimensions == 3:
        from ..model.initial import initial_values

        for warning in initial_values(model).warnings:   # Euler parameters normalized
            print(f"flexkane: warning: {warning}", file=sys.stderr)
    free = [c for c in coordinates if c.driver is None]
    modes = ", ".join(f"{b.name}: {b.modes_text()}" for b in model.beams.values())
    speeds = sum(c.u is not None for c in coordinates)
    print(f"{args.model}: valid ({'spatial, ' if model.dimensions == 3 else ''}{len(model.bodies)} bodies, "
          f"{len(model.beams)} beams"
          + (f" [{modes}]" if modes else "") + f", {len(model.joints)} joints"
          + (f", {len(model.constraints)} loop constraints" if model.constraints else "")
          + f"; {len(coordinates)} generalized coordinates: "
          f"{', '.join(c.q for c in coordinates)}"
          + (f"; {speeds} generalized speeds" if speeds != len(coordinates) else "")
          + (f"; {len(coordinates) - len(free)} prescribed by drivers" if len(free) < len(coordinates)
             else "") + ")" + (f"; [sweep] of {sweep} variant(s)" if sweep else ""))
    return 0


def _check_sweep_table(spec: str, model) -> int | None:
    """Check the [sweep] table of the model file, if it has one; return its number of variants."""
    import tomllib

    from .sweep import _model_text

    text = _model_text(spec)
    if not text or "sweep" not in tomllib.loads(text):   # the model loaded: the TOML is valid
        return None
    from ..sweep.spec import sweep_spec_from_toml
    from ..sweep.variants import RunSettings, check_sweep

    sweep = sweep_spec_from_toml(text)
    return check_sweep(model, sweep, RunSettings.resolve(sweep, model))
