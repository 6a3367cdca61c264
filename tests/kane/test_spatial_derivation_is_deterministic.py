"""The derivation and the generated code of a spatial chain do not depend on the process: two
interpreters with different string hashing (``PYTHONHASHSEED``) give the same module source."""

import subprocess
import sys

import pytest

from child_env import child_env

CHILD = """
import hashlib
import flexkane
from flexkane.derivation_cache import model_source
from flexkane.model import loads_model

lines = ["dimensions = 3", "[gravity]", "g = 9.81", "direction = [0, 0, -1]"]
for i in range(2):
    parent = "ground" if i == 0 else f"b{i - 1}"
    lines += [f"[bodies.b{i}]", "mass = 1.0", "inertia = [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.15]]",
              "points = { top = [0, 0, 0.5], bottom = [0.05, 0, -0.5] }", f"[joints.j{i}]", 'type = "spherical"',
              f'parent = "{parent}"', f'child = "b{i}"', 'child_point = "top"']
    lines += ['parent_point = "bottom"'] if i else []
eom = flexkane.derive(loads_model("\\n".join(lines)), cache=False)
print(hashlib.sha256(model_source(eom).encode()).hexdigest())
"""


@pytest.mark.slow
def test_generated_code_of_a_spherical_chain_is_the_same_in_every_process():
    digests = set()
    for seed in ("1", "2", "3"):
        done = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=600,
                              env=child_env(PYTHONHASHSEED=seed))
        assert done.returncode == 0, done.stderr
        digests.add(done.stdout.strip().splitlines()[-1])
    assert len(digests) == 1
