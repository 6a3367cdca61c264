"""Derive a model recording every attribute written on the equations and every call of a reduction.

Used by the tests that check that the reductions of Kane's equations (drivers of the state, closed
loops) are values: pure functions of the equations over the free speeds, each attribute of
:class:`~flexkane.kane.equations.EquationsOfMotion` set once from them.
"""

from __future__ import annotations

import dataclasses
from collections import Counter

import pytest
import sympy as sp

from flexkane.kane import equations
from flexkane.kane.constraints import ConstraintSet


class RecordingEquations(equations.EquationsOfMotion):
    """Counts, in ``writes``, how many times each attribute is assigned while the equations are built."""

    def __setattr__(self, name, value):
        self.__dict__.setdefault("writes", Counter())[name] += 1
        super().__setattr__(name, value)


def snapshot(value):
    """A copy of a reduction's argument to compare it with afterwards (None for the chain and callables)."""
    if isinstance(value, sp.MatrixBase):
        return value.copy()
    if isinstance(value, ConstraintSet):
        return dataclasses.replace(value, **{f.name: list(getattr(value, f.name)) for f in dataclasses.fields(value)})
    if isinstance(value, dict):
        return dict(value)
    if isinstance(value, (list, tuple)):
        return list(value)
    return None


def derive_recording(model, name: str, function):
    """``(eom, calls)``: the equations of ``model`` derived by :class:`RecordingEquations`, and each call
    of the module function ``kane.equations.<name>`` (which is ``function``) as ``(args, kwargs,
    snapshots of the args before the call, result)``."""
    calls = []

    def recording(*args, **kwargs):
        before = [snapshot(a) for a in args]
        result = function(*args, **kwargs)
        calls.append((args, kwargs, before, result))
        return result

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(equations, "EquationsOfMotion", RecordingEquations)
        patch.setattr(equations, name, recording)
        eom = equations.derive(model)    # afresh (the cache would load stored equations)
    return eom, calls
