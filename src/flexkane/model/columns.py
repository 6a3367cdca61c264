"""The columns of a run's results, named from the model's structure, and their uniqueness.

A results file has one column per name: ``t``, the state variables (the coordinates, the speeds and
the controller states, :mod:`flexkane.model.coordinates`), then the outputs that
:mod:`flexkane.kane.outputs`, :mod:`flexkane.kane.spatial_outputs`, :mod:`flexkane.kane.controllers`
and :mod:`flexkane.kane.loop_reduction` compute, and ``work`` and ``energy_balance`` of the run.
Several of these names are made from names of the model file (``x_<body>``, ``yaw_<body>``,
``sensor_<name>``, ``u_<joint>``, a controller state's own name), so a model could give one name to two
columns: a controller state ``energy`` or a body ``cm`` (``x_cm``) would replace the physical column.

:func:`result_columns` names every column from the model's structure alone (no derivation) and
refuses a model whose names collide, with a :class:`~flexkane.errors.ModelError` naming the field
that gives the second name, what the name already is and the name given. The validation calls it, so
``flexkane check`` refuses such a model; :class:`ColumnTable` is the guard where the outputs are
assembled: a name made twice there is an internal error, never a silent overwrite.
"""

from __future__ import annotations

from ..errors import ModelError
from .coordinates import BEAM_ROLES

__all__ = ["ColumnTable", "DuplicateColumnError", "result_columns"]

#: Columns of the whole system, by the chain's dimensions, with what each is (for messages).
_SYSTEM = {
    2: {"x_cm": "x of the system's mass centre", "y_cm": "y of the system's mass centre",
        "p_x": "the system's momentum along x", "p_y": "the system's momentum along y",
        "h_o": "the system's angular momentum about the origin",
        "h_cm": "the system's angular momentum about its mass centre"},
    3: {**{f"{a}_cm": f"{a} of the system's mass centre" for a in "xyz"},
        **{f"p_{a}": f"the system's momentum along {a}" for a in "xyz"},
        **{f"H_{a}": f"the system's angular momentum about its mass centre along {a}" for a in "xyz"}},
}
#: Energy and work columns of every model.
_ENERGY = {"kinetic": "the kinetic energy", "potential_gravity": "the potential energy of gravity",
           "strain": "the strain energy", "potential_springs": "the energy of the springs",
           "energy": "the total energy", "power_nonconservative": "the power of the non-conservative forces",
           "work": "the work of the non-conservative forces", "energy_balance": "the energy balance"}
#: Number of scalar constraints of a planar loop constraint, by type (spatial: validate_spatial).
_PLANAR_CONSTRAINT_EQUATIONS = 2


class DuplicateColumnError(RuntimeError):
    """An output column made twice while the results are assembled: a defect of flexkane, since
    :func:`result_columns` refused every model whose names collide."""


class ColumnTable(dict):
    """Output expressions or arrays by column name, each name set once.

    ``table[name] = value`` and ``update`` raise :class:`DuplicateColumnError` for a name already
    present; :meth:`replace` changes the value of a present name on purpose (the loops' reduction
    corrects the drivers' efforts).
    """

    def __setitem__(self, name, value):
        if name in self:
            raise DuplicateColumnError(f"internal error: the output column {name!r} was made twice "
                                       "(the validation should have refused the model's names)")
        super().__setitem__(name, value)

    def update(self, *others, **named):
        for other in (*others, named):
            for name, value in dict(other).items():
                self[name] = value

    def setdefault(self, name, value=None):
        if name not in self:
            self[name] = value
        return self[name]

    def replace(self, name, value) -> None:
        """Set the value of a column already present."""
        if name not in self:
            raise DuplicateColumnError(f"internal error: the output column {name!r} is replaced but was never made")
        super().__setitem__(name, value)


class _Claims:
    """Column names and the field that gave each."""

    def __init__(self):
        self.owner: dict[str, tuple[str | None, str]] = {}

    def claim(self, path: str | None, what: str, names, given=None) -> None:
        """Claim ``names`` for the field ``path`` (None: the system), each described by ``what``
        (a text, or a function of the name)."""
        names = list(dict.fromkeys(names))
        for name in names:
            if name in self.owner:
                other_path, other_what = self.owner[name]
                where = f" (from {other_path})" if other_path else ""
                whose = "that is not already a column of the results" if names == [name] and given is None \
                    else f"whose result columns ({', '.join(names)}) are not already columns of the results"
                raise ModelError(path, f"a name {whose} ({name!r} is {other_what}{where})",
                                 name if given is None else given)
        for name in names:
            self.owner.setdefault(name, (path, what(name) if callable(what) else what))


def result_columns(model, coordinates) -> dict[str, str]:
    """Name every column of the model's results; refuse two columns of one name.

    Parameters
    ----------
    model : Model
        A model whose parts, references and signals are valid.
    coordinates : list of CoordinateName
        Its coordinates (:func:`flexkane.model.coordinates.coordinate_names`).

    Returns
    -------
    dict of str to str
        Every column name (``t``, the state variables, the outputs, ``work``, ``energy_balance``) to
        what it is, in no particular order (results.csv orders them, :mod:`flexkane.results`).

    Raises
    ------
    ModelError
        For a name of the model that gives a column already given by another part (or by the
        system: ``energy``, ``x_cm``, ...), naming the field, what the column already is and the
        name given.
    """
    dims = model.dimensions
    claims = _Claims()
    claims.claim(None, "the time", ["t"])
    claims.claim(None, lambda n: _SYSTEM[dims][n], list(_SYSTEM[dims]))
    claims.claim(None, lambda n: _ENERGY[n], list(_ENERGY))
    for name in model.bodies:
        claims.claim(f"bodies.{name}", f"a column of body {name!r}", _body_columns(name, dims), name)
    for name, beam in model.beams.items():
        claims.claim(f"beams.{name}", f"a column of beam {name!r}", _beam_columns(beam, dims), name)
    for joint in model.joints.values():
        names = []
        if joint.torque is not None or joint.driver is not None:
            names.append(f"effort_{joint.name}")
        if dims == 3 and joint.type in ("spherical", "free"):
            names.append(f"quaternion_norm_{joint.name}")
        claims.claim(f"joints.{joint.name}", f"a column of joint {joint.name!r}", names, joint.name)
    for load in model.loads.values():
        names = [f"load_{load.name}_f{a}" for a in "xyz"[:dims]] if load.force is not None else []
        if load.torque is not None:
            names += [f"load_{load.name}_t{a}" for a in "xyz"] if dims == 3 else [f"load_{load.name}_torque"]
        claims.claim(f"loads.{load.name}", f"a column of load {load.name!r}", names, load.name)
    for sensor in model.sensors:
        claims.claim(f"sensors.{sensor}", f"the column of sensor {sensor!r}", [f"sensor_{sensor}"], sensor)
    for ctrl in model.controllers.values():
        if ctrl.output is not None:
            claims.claim(f"controllers.{ctrl.name}", f"the output of controller {ctrl.name!r}",
                         [f"controller_{ctrl.name}"], ctrl.name)
    for con in model.constraints.values():
        count = _constraint_equations(con, dims)
        claims.claim(f"constraints.{con.name}", f"a residual of loop constraint {con.name!r}",
                     [f"constraint_{con.name}_{k + 1}" for k in range(count)], con.name)
    # the state variables last: a name the file gives a column directly is the one to change
    for c in coordinates:
        joint = model.joints.get(c.owner)
        for kind, name, names_key in (("coordinate", c.q, "coordinates"), ("speed", c.u, "speeds")):
            # a driver makes its speed (and a prescribed coordinate) a function of t: no column
            if name is None or (c.driver is not None and (kind == "speed" or c.driver == "coordinate")):
                continue
            listed = getattr(joint, names_key, None) if joint is not None and c.role not in BEAM_ROLES else None
            if listed and name in listed:
                path = f"joints.{c.owner}.{names_key}[{list(listed).index(name)}]"
            else:
                path = f"{'beams' if c.role in BEAM_ROLES else 'joints'}.{c.owner}"
            claims.claim(path, f"the {kind} {name} (a state variable)", [name])
    for ctrl in model.controllers.values():
        for state in ctrl.states:
            claims.claim(f"controllers.{ctrl.name}.states.{state}", f"the state {state} of controller {ctrl.name!r}",
                         [state])
    return {name: what for name, (_, what) in claims.owner.items()}


def _body_columns(name: str, dims: int) -> list[str]:
    """``x_<b>, y_<b>, theta_<b>`` (planar); ``x_, y_, z_, e0_ .. e3_, yaw_, pitch_, roll_<b>`` (3D)."""
    if dims == 2:
        return [f"x_{name}", f"y_{name}", f"theta_{name}"]
    return [*(f"{a}_{name}" for a in "xyz"), *(f"e{k}_{name}" for k in range(4)),
            *(f"{a}_{name}" for a in ("yaw", "pitch", "roll"))]


def _beam_columns(beam, dims: int) -> list[str]:
    """A beam's root frame and tip: planar ``x_, y_, theta_, tip_<b>``; spatial ``x_, y_, z_,
    e0_ .. e3_<b>``, ``tip_<b>_y``, ``slope_<b>_y`` (and ``_z``) for each bending plane with modes and
    ``twist_<b>`` with torsion modes."""
    name = beam.name
    if dims == 2:
        return [f"x_{name}", f"y_{name}", f"theta_{name}", f"tip_{name}"]
    names = [*(f"{a}_{name}" for a in "xyz"), *(f"e{k}_{name}" for k in range(4))]
    for label in ("y", "z"):
        if getattr(beam, f"n_modes_{label}"):
            names += [f"tip_{name}_{label}", f"slope_{name}_{label}"]
    if beam.n_torsion:
        names.append(f"twist_{name}")
    return names


def _constraint_equations(con, dims: int) -> int:
    if dims == 3:
        from .validate_spatial import CONSTRAINT_EQUATIONS

        return CONSTRAINT_EQUATIONS[con.type]
    return _PLANAR_CONSTRAINT_EQUATIONS
