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
``flexkane check`` refuses such a model.

Each output is declared where it is made, as an :class:`Output`: its name, its value (a SymPy
expression while the equations are derived, an array along a run), its unit and its group
(:data:`GROUPS`: tip deflections, efforts, energies ...). An :class:`Outputs` collection holds them
and refuses a name made twice (an internal error, never a silent overwrite), so the names of a
run's outputs are unique by construction. The unit lookup, the order of results.csv and the
grouping of the plots read these declarations.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from ..errors import ModelError
from .coordinates import BEAM_ROLES

__all__ = ["Output", "OutputGroup", "Outputs", "GROUPS", "ENERGIES", "DuplicateColumnError", "result_columns",
           "constraint_residual_units"]

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
#: The energies of a system, in the order of the results, with what each is (their sum is ``energy``).
ENERGIES = {"kinetic": "the kinetic energy", "potential_gravity": "the potential energy of gravity",
            "strain": "the strain energy", "potential_springs": "the energy of the springs"}
#: Energy and work columns of every model.
_ENERGY = {**ENERGIES, "energy": "the total energy",
           "power_nonconservative": "the power of the non-conservative forces",
           "work": "the work of the non-conservative forces", "energy_balance": "the energy balance"}
#: Number of scalar constraints of a planar loop constraint, by type (spatial: validate_spatial).
_PLANAR_CONSTRAINT_EQUATIONS = 2


class DuplicateColumnError(RuntimeError):
    """An output column made twice while the results are assembled: a defect of flexkane, since
    :func:`result_columns` refused every model whose names collide."""


@dataclass(frozen=True)
class OutputGroup:
    """A kind of output: what its columns are and where results.csv writes them.

    Attributes
    ----------
    name : str
        The group's name (an :attr:`Output.group`).
    what : str
        What its columns are (for messages and documents).
    csv : int or None
        Rank of its columns in results.csv, after the state: the columns of rank 1, then 2, then 3,
        each rank in the order the columns were made; None: not written to results.csv (results.npz
        holds every output).
    """

    name: str
    what: str
    csv: int | None


#: The groups of outputs, by name.
GROUPS = {g.name: g for g in (
    OutputGroup("position", "a position in N: mass centre of a body or of the system, root of a beam", None),
    OutputGroup("frame_angle", "the angle of a planar body's or beam's frame", None),
    OutputGroup("orientation", "an Euler parameter of a spatial body's or beam's frame in N", None),
    OutputGroup("attitude", "a 3-2-1 angle (yaw, pitch, roll) of a spatial body's frame in N", 2),
    OutputGroup("tip", "the deflection of a beam's tip", 1),
    OutputGroup("slope", "the slope of a spatial beam's tip", None),
    OutputGroup("twist", "the twist of a spatial beam's tip section", 2),
    OutputGroup("momentum", "the linear or angular momentum of the system (planar: about the origin or the "
                            "mass centre)", None),
    OutputGroup("angular_momentum", "the angular momentum of a spatial system about its mass centre, ground axes",
                3),
    OutputGroup("quaternion_norm", "the norm of a joint's Euler parameters minus 1", 2),
    OutputGroup("energy", "an energy of the system, the work done on it or its energy balance", 3),
    OutputGroup("power", "the power of the non-conservative forces", None),
    OutputGroup("effort", "the generalized force of a joint's driver", 1),
    OutputGroup("actuator", "the torque or force of a joint's actuator (its torque field)", 1),
    OutputGroup("load", "a component of an applied load, as given", 1),
    OutputGroup("sensor", "a sensor's reading", 1),
    OutputGroup("controller", "a controller's output, saturated", 1),
    OutputGroup("constraint", "the residual of a loop constraint", None),
    OutputGroup("dependent_speed", "a dependent speed of a closed loop", None),
    OutputGroup("input", "the effort a controller in the loop gives an input channel", None),
)}


@dataclass(frozen=True)
class Output:
    """An output of a model, declared where it is made.

    Attributes
    ----------
    name : str
        Its column name in the results.
    value : object
        A SymPy expression while the equations are derived, an array (N,) along a run, None in a
        declaration alone (:meth:`declaration`).
    unit : str or None
        Its unit, as the fields write theirs (``"m"``, ``"N m"``, ``"kg m^2/s"``, ``"-"``
        dimensionless); None only for a controller's output whose unit the model's expressions do
        not fix (:func:`flexkane.model.signal_units.controller_units`).
    group : str
        Its kind, a key of :data:`GROUPS`.
    description : str
        What it is, in words.
    """

    name: str
    value: object
    unit: str | None
    group: str
    description: str = ""

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"internal error: an output is named {self.name!r}, not a text")
        if self.group not in GROUPS:
            raise ValueError(f"internal error: the output {self.name!r} is in the group {self.group!r}, "
                             f"not one of {', '.join(GROUPS)}")
        if self.unit is None and self.group != "controller":
            raise ValueError(f"internal error: the output {self.name!r} ({self.group}) has no unit")

    def declaration(self) -> "Output":
        """The output without its value: name, unit, group and description."""
        return replace(self, value=None)

    def to_json(self) -> list:
        """``[name, unit, group, description]`` (:meth:`from_json` inverts it)."""
        return [self.name, self.unit, self.group, self.description]

    @classmethod
    def from_json(cls, data) -> "Output":
        """The declaration that :meth:`to_json` wrote."""
        name, unit, group, description = data
        return cls(name, None, unit, group, description)

    def __str__(self) -> str:
        unit = "unit not fixed" if self.unit is None else self.unit
        return f"{self.description or self.group} [{unit}]"


class Outputs(Mapping):
    """Outputs by name, in the order they were made; each name once.

    As a mapping it gives each output's value (``outputs["energy"]``); :meth:`output` gives the
    whole :class:`Output`. :meth:`add` refuses a name already present with a
    :class:`DuplicateColumnError` that says what both are; :meth:`replace` changes the value of a
    present name on purpose (the loops' reduction corrects the drivers' efforts).

    Parameters
    ----------
    outputs : iterable of Output, optional
    """

    def __init__(self, outputs=()):
        self._outputs: dict[str, Output] = {}
        for output in outputs:
            self.put(output)

    def put(self, output: Output) -> None:
        """Add ``output``; refuse its name if present."""
        if output.name in self._outputs:
            raise DuplicateColumnError(
                f"internal error: the output column {output.name!r} was made twice, as "
                f"{self._outputs[output.name]} and as {output} (the validation should have refused the "
                "model's names)")
        self._outputs[output.name] = output

    def add(self, name: str, value, unit: str | None, group: str, description: str = ""):
        """Declare and add the output ``name``; return its value."""
        self.put(Output(name, value, unit, group, description))
        return value

    def replace(self, name: str, value) -> None:
        """Set the value of an output already present (its declaration kept)."""
        if name not in self._outputs:
            raise DuplicateColumnError(f"internal error: the output column {name!r} is replaced but was never made")
        self._outputs[name] = replace(self._outputs[name], value=value)

    def output(self, name: str) -> Output:
        """The whole output ``name``."""
        return self._outputs[name]

    def copy(self) -> "Outputs":
        """The same outputs in a new collection."""
        return Outputs(self._outputs.values())

    def map(self, function) -> "Outputs":
        """The outputs with ``function`` applied to every value, declarations kept."""
        return Outputs(replace(o, value=function(o.value)) for o in self._outputs.values())

    def declarations(self) -> list[Output]:
        """Every output without its value, in order."""
        return [o.declaration() for o in self._outputs.values()]

    @classmethod
    def of(cls, declarations, values: Mapping) -> "Outputs":
        """The outputs of ``declarations`` (Output, values ignored) with the values of ``values``
        (a mapping of every declared name and no other)."""
        undeclared = set(values) - {d.name for d in declarations}
        if undeclared:
            raise RuntimeError(f"internal error: the output column(s) {', '.join(sorted(undeclared))} "
                               "were made without a declaration")
        return cls(replace(d, value=values[d.name]) for d in declarations)

    def __getitem__(self, name: str):
        return self._outputs[name].value

    def __iter__(self):
        return iter(self._outputs)

    def __len__(self) -> int:
        return len(self._outputs)

    def __repr__(self) -> str:
        return f"Outputs({list(self._outputs)})"


def constraint_residual_units(con, dims: int) -> list[str]:
    """Units of the residuals ``constraint_<name>_<k>`` of a loop constraint, in order: a planar
    revolute closes x and y [m], a planar prismatic a distance and an angle [m, rad]; a spatial
    spherical closes x, y, z [m], a point on a line two distances [m], a weld x, y, z [m] and the
    axial vector of the relative orientation's skew part [-] (:mod:`flexkane.kane.spatial_constraints`)."""
    if dims == 2:
        return ["m", "m"] if con.type == "revolute" else ["m", "rad"]
    return {"spherical": ["m"] * 3, "point_on_line": ["m"] * 2, "weld": ["m"] * 3 + ["-"] * 3}[con.type]


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
