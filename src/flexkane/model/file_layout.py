"""The layout of a model file: the keys each of its tables may have, and the orientation tables.

:mod:`flexkane.model.toml_io` checks a file against these tables (each the keys its declaration in
:mod:`flexkane.model.schema` gives) (a key not listed is refused, with the
nearest valid key); :mod:`flexkane.model.paths` reads them to say which keys a path may name. An
orientation (:class:`~flexkane.model.parts.Orientation`) is given as a table in either of the two forms of
:data:`ORIENTATION_FORMS`; :func:`orientation_from_table` reads one, in a model file or in Python.
"""

from __future__ import annotations

import difflib

from ..errors import ModelError
from . import schema
from .parts import Orientation

__all__ = ["BEAM_KEYS", "BODY_KEYS", "CONSTRAINT_KEYS", "CONTROLLER_KEYS", "DISTRIBUTED_KEYS", "DRIVER_KEYS",
           "GRAVITY_KEYS", "JOINT_KEYS", "LOAD_KEYS", "ORIENTATION_FORMS", "ORIENTATION_KEYS", "SENSOR_KEYS",
           "SHAPE_KEYS", "SIM_KEYS", "SPATIAL_BEAM_KEYS", "SPRING_KEYS", "TOP_KEYS", "orientation_from_table"]

# The keys of each table, in the order the file is written (declared in :mod:`flexkane.model.schema`).
#: Top-level keys of a model file.
TOP_KEYS = schema.TOP.keys(2)
BODY_KEYS = schema.BODIES.keys(2)
BEAM_KEYS = schema.BEAMS.keys(2)
#: Keys of a beam in a spatial model (dimensions = 3): two bending planes, torsion, axial stretch.
SPATIAL_BEAM_KEYS = schema.BEAMS.keys(3)
SHAPE_KEYS = schema.SHAPE.keys(2)  # plus the options of the family, checked by the family
JOINT_KEYS = schema.JOINTS.keys(2)
DRIVER_KEYS = schema.DRIVER.keys(2)
GRAVITY_KEYS = schema.GRAVITY.keys(2)
LOAD_KEYS = schema.LOADS.keys(2)
DISTRIBUTED_KEYS = schema.DISTRIBUTED_LOADS.keys(2)
SPRING_KEYS = schema.SPRINGS.keys(2)
CONSTRAINT_KEYS = schema.CONSTRAINTS.keys(2)
SENSOR_KEYS = schema.SENSORS.keys(2)
CONTROLLER_KEYS = schema.CONTROLLERS.keys(2)
SIM_KEYS = schema.SIMULATION.keys(2)

#: Keys of an orientation table.
ORIENTATION_KEYS = ("axis", "angle", "sequence", "angles")
#: What an orientation table looks like, for messages.
ORIENTATION_FORMS = ("a table { axis = [ax, ay, az], angle = a } or { sequence = \"zyx\", angles = [a1, a2, a3] }"
                     " (sequence: 1 to 3 letters among x, y, z; angles [rad])")


def orientation_from_table(table, path: str) -> Orientation:
    """An :class:`~flexkane.model.parts.Orientation` from a model file's table (keys checked; values
    kept as given for the validation).

    Parameters
    ----------
    table : dict or Orientation
        ``{ axis = [...], angle = ... }`` or ``{ sequence = "...", angles = [...] }``.
    path : str
        Key path of the table, for messages.

    Raises
    ------
    ModelError
        For a value that is not a table, an unknown key, or keys of both forms.
    """
    if isinstance(table, Orientation):
        return table
    if not isinstance(table, dict):
        raise ModelError(path, ORIENTATION_FORMS, table)
    for key in table:
        if key not in ORIENTATION_KEYS:
            close = difflib.get_close_matches(str(key), ORIENTATION_KEYS, n=1, cutoff=0.5)
            raise ModelError(f"{path}.{key}", "a known key of an orientation (axis, angle or sequence, angles)",
                             key, f"did you mean {close[0]!r}?" if close else None)
    axis, angles = table.get("axis"), table.get("angles")
    return Orientation(axis=tuple(axis) if isinstance(axis, list) else axis, angle=table.get("angle"),
                       sequence=table.get("sequence"), angles=list(angles) if isinstance(angles, tuple) else angles)
