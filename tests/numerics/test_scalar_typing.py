"""Numba's typing of scalar arithmetic memoized (flexkane.numerics.scalar_typing): the signature is the one
Numba computes itself, failures are not remembered, and compiled right-hand sides give the same bits."""

import json
import operator
import subprocess
import sys
from pathlib import Path

import pytest
from numba.core import errors, types
from numba.core.registry import cpu_target
from numba.core.types.functions import BaseFunction

from flexkane.numerics import scalar_typing

from child_env import child_env


def _function_type(value):
    context = cpu_target.typing_context
    context.refresh()
    return context, context.resolve_value_type(value)


@pytest.mark.parametrize("value, args", [
    (operator.mul, (types.float64, types.float64)),
    (operator.add, (types.int64, types.float64)),
    (operator.truediv, (types.float64, types.int64)),
    (operator.pow, (types.float64, types.float64)),
    (operator.lt, (types.float64, types.float64)),
])
def test_memoized_typing_is_numbas_own_signature_and_is_reused(value, args):
    assert scalar_typing.install()
    assert scalar_typing.installed() and scalar_typing.install()   # idempotent
    context, function = _function_type(value)
    own = BaseFunction.get_call_type.__wrapped__(function, context, args, {})
    first = function.get_call_type(context, args, {})
    again = function.get_call_type(context, args, {})
    assert first == own
    assert again is first      # the second typing is the memoized answer


def test_a_typing_failure_is_not_memoized_and_still_raises():
    assert scalar_typing.install()
    context, function = _function_type(operator.lshift)
    for _ in range(2):        # float << float does not type, the second time either
        with pytest.raises(errors.TypingError):
            function.get_call_type(context, (types.float64, types.float64), {})


_CHILD = r"""
import importlib.util, json, sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, sys.argv[2])
import flexkane
from flexkane.numerics import scalar_typing
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.numerics.jit_module import compose_module_source
from scaling import chain_model
if sys.argv[1] == "memoized":
    assert scalar_typing.install()
result = {}
for label, model in (("chain_model(3)", chain_model(3)), ("four-bar", flexkane.builtin_model("four-bar"))):
    eom = flexkane.derive(model, cache=False)
    path = Path(tempfile.mkdtemp()) / f"m{len(result)}.py"
    path.write_text(compose_module_source(generate_rhs_source(eom), "test"))
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)
    rng = np.random.default_rng(7)
    n = len(eom.q) + len(eom.u)
    p = eom.parameter_vector()
    rows = []
    for _ in range(20):
        dy = np.empty(n)
        module.rhs(float(rng.uniform(0, 1)), rng.standard_normal(n) * 0.5, p, dy)
        rows.append(dy.tobytes().hex())
    result[label] = rows
print(json.dumps({"installed": scalar_typing.installed(), "rows": result}))
"""


@pytest.mark.slow
def test_right_hand_sides_compiled_with_memoized_typing_give_the_same_bits(tmp_path):
    benchmarks = str(Path(__file__).resolve().parents[2] / "benchmarks")
    runs = {}
    for mode in ("numba", "memoized"):
        done = subprocess.run([sys.executable, "-c", _CHILD, mode, benchmarks], capture_output=True,
                              text=True, env=child_env(FLEXKANE_CACHE_DIR=str(tmp_path)), timeout=900)
        assert done.returncode == 0, done.stderr[-2000:]
        runs[mode] = json.loads(done.stdout.strip().splitlines()[-1])
    assert not runs["numba"]["installed"] and runs["memoized"]["installed"]
    assert runs["numba"]["rows"] == runs["memoized"]["rows"]
