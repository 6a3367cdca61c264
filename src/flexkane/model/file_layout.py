"""The layout of a model file: the keys each of its tables may have, and the orientation tables.

:mod:`flexkane.model.toml_io` checks a file against these tables (a key not listed is refused, with the
nearest valid key); :mod:`flexkane.model.paths` reads them to say which keys a path may name. An
orientation (:class:`~flexkane.model.parts.Orientation`) is given as a table in either of the two forms of
:data:`ORIENTATION_FORMS`; :func:`orientation_from_table` reads one, in a model file or in Python.
"""

from __future__ import annotations

import difflib

from ..errors import ModelError
from .parts import Orientation

__all__ = ["BEAM_KEYS", "BODY_KEYS", "CONSTRAINT_KEYS", "CONTROLLER_KEYS", "DISTRIBUTED_KEYS", "DRIVER_KEYS",
           "GRAVITY_KEYS", "JOINT_KEYS", "LOAD_KEYS", "ORIENTATION_FORMS", "ORIENTATION_KEYS", "SENSOR_KEYS",
           "SHAPE_KEYS", "SIM_KEYS", "SPATIAL_BEAM_KEYS", "SPRING_KEYS", "TOP_KEYS", "orientation_from_table"]

#: Top-level keys of a model file.
TOP_KEYS = ("name", "dimensions", "description", "naming", "parameters", "bodies", "beams", "joints", "gravity",
            "loads", "distributed_loads", "springs", "constraints", "sensors", "controllers", "initial", "simulation",
            "sweep")
BODY_KEYS = ("mass", "inertia", "points", "outline")
BEAM_KEYS = ("L", "EI", "rho", "n_modes", "shape", "damping", "gravity", "elastic_forces",
             "geometric_stiffening", "EA", "n_axial", "axial_shape", "rotary_inertia", "static_corrections")
#: Keys of a beam in a spatial model (dimensions = 3): two bending planes, torsion, axial stretch.
SPATIAL_BEAM_KEYS = ("L", "rho", "EI_y", "EI_z", "n_modes_y", "n_modes_z", "shape_y", "shape_z", "GJ",
                     "rho_Ip", "n_torsion", "torsion_shape", "EA", "n_axial", "axial_shape",
                     "principal_angle", "damping", "gravity", "geometric_stiffening", "rotary_inertia",
                     "rho_Iy", "rho_Iz", "damping_y", "damping_z", "torsion_damping", "axial_damping",
                     "static_corrections")
SHAPE_KEYS = ("family", "roots")  # plus the options of the family, checked by the family
JOINT_KEYS = ("type", "parent", "child", "parent_point", "parent_position", "station", "child_point",
              "angle", "axis", "axes", "orientation", "child_orientation", "coordinates", "speeds", "stiffness",
              "damping", "rest", "torque", "driver")
DRIVER_KEYS = ("coordinate", "speed")
GRAVITY_KEYS = ("g", "direction")
LOAD_KEYS = ("body", "point", "station", "force", "torque", "frame")
DISTRIBUTED_KEYS = ("beam", "fx", "fy", "frame", "quadrature_nodes")
SPRING_KEYS = ("body_a", "point_a", "station_a", "position_a", "body_b", "point_b", "station_b", "position_b",
               "stiffness", "damping", "rest_length")
CONSTRAINT_KEYS = ("type", "body_a", "point_a", "station_a", "position_a", "body_b", "point_b", "station_b",
                   "position_b", "axis", "angle", "dependent", "stabilization", "orientation")
SENSOR_KEYS = ("type", "beam", "body", "point", "joint", "station", "distance", "frame", "component")
CONTROLLER_KEYS = ("states", "initial", "output", "min", "max")
SIM_KEYS = ("t_end", "dt_out", "rtol", "atol", "method", "max_steps", "deflection_warning", "spin_warning")

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
