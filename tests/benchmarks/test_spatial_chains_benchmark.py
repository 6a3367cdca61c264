"""The models and the report of benchmarks/spatial_chains.py (issue 17, Performance).

The flexible arms of the growth table are the built-in robot-arm-3d-flexible with other numbers of
links and modes: two links of 2 modes per plane give the built-in's coordinates, and each link adds
its 2 n + 1 elastic coordinates and an elbow; the targets are judged on CPU time.
"""

from __future__ import annotations

import pathlib
import sys

import flexkane
from flexkane.builtin import builtin_text
from flexkane.model.coordinates import coordinate_names

BENCHMARKS = pathlib.Path(__file__).resolve().parents[2] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import spatial_chains  # noqa: E402


def _coordinates(text):
    return [c.q for c in coordinate_names(flexkane.loads_model(text).validate())]


def test_flexible_arm_variants_grow_the_built_in_arm_by_links_and_modes():
    builtin = _coordinates(builtin_text("robot-arm-3d-flexible"))
    same = _coordinates(spatial_chains.flexible_arm(2, 2))
    rename = {"upper": "link1", "fore": "link2", "elbow": "elbow1"}
    renamed = []
    for name in builtin:
        for old, new in rename.items():
            name = name.replace(f"_{old}", f"_{new}")
        renamed.append(name)
    assert same == renamed
    for links, modes in ((1, 1), (1, 2), (3, 2), (2, 4)):
        count = len(_coordinates(spatial_chains.flexible_arm(links, modes)))
        assert count == 2 + links * (2 * modes + 1) + (links - 1)       # waist, shoulder; elbows


def test_targets_are_judged_on_cpu_time():
    row = {"total": 18.0, "simulate": 2.0, "simulate_cpu": 0.2}
    (build, build_met, _), (motion, motion_met, measured) = spatial_chains.targets({"flexible": row})
    assert build_met and motion_met and "0.20 s CPU" in measured
    row["simulate_cpu"] = 1.5
    assert not spatial_chains.targets({"flexible": row})[1][1]
    assert spatial_chains.targets({"flexible": {"error": "failed"}}) == []
