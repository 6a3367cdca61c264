"""The model: a chain of rigid bodies and beams, planar or spatial, with its parameters and initial
conditions."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

from ..errors import ModelError
from .parts import (DIMENSIONS, NAMING_STYLES, Beam, Controller, DistributedLoad, Gravity, Joint, Load,
                    LoopConstraint, PointSpring, RigidBody, Sensor, Simulation, Value)

__all__ = ["Model", "NAMING_STYLES", "DIMENSIONS"]


@dataclass
class Model:
    """A kinematic chain with continuous flexible links, in the plane or in space.

    The same content as a TOML model file (:func:`flexkane.model.load_model`,
    :func:`flexkane.model.dumps_model`). Build one in Python by filling the dictionaries, then call
    :meth:`validate` (done by every pipeline stage).

    Parameters
    ----------
    name : str
        Model name (used in output titles).
    parameters : dict of str to Value
        Named parameters; any field may refer to them. They stay symbols in the derived equations.
    bodies : dict of str to RigidBody
    beams : dict of str to Beam
    joints : dict of str to Joint
    gravity : Gravity, optional
    loads : dict of str to Load
    distributed_loads : dict of str to DistributedLoad
        Forces per unit length along beams.
    springs : dict of str to PointSpring
    constraints : dict of str to LoopConstraint
        Joints that close kinematic loops.
    initial : dict of str to Value
        Initial values of generalized coordinates and speeds, by name; others start at 0.
    sensors : dict of str to Sensor
        Named outputs usable in effort expressions.
    controllers : dict of str to Controller
        Controller states (extra first-order states) and outputs.
    naming : str
        One of :data:`NAMING_STYLES`.
    simulation : Simulation
        Default run settings.
    description : str
        Free text.
    dimensions : int
        2 for a planar chain (two-component vectors, scalar inertias and angles), 3 for a spatial
        one (three-component vectors, inertia tensors, joint axes and orientations); one of
        :data:`~flexkane.model.parts.DIMENSIONS`.
    control_inputs : bool
        Derive the control inputs (actuator efforts and load components, :mod:`flexkane.kane.inputs`)
        as symbols of the equations; set by ``simulate(..., controller=f)`` and ``linearize`` on
        their copies, not a model-file key.
    """

    name: str = "model"
    parameters: dict[str, Value] = field(default_factory=dict)
    bodies: dict[str, RigidBody] = field(default_factory=dict)
    beams: dict[str, Beam] = field(default_factory=dict)
    joints: dict[str, Joint] = field(default_factory=dict)
    gravity: Gravity | None = None
    loads: dict[str, Load] = field(default_factory=dict)
    distributed_loads: dict[str, DistributedLoad] = field(default_factory=dict)
    springs: dict[str, PointSpring] = field(default_factory=dict)
    constraints: dict[str, LoopConstraint] = field(default_factory=dict)
    initial: dict[str, Value] = field(default_factory=dict)
    sensors: dict[str, Sensor] = field(default_factory=dict)
    controllers: dict[str, Controller] = field(default_factory=dict)
    naming: str = "joint"
    simulation: Simulation = field(default_factory=Simulation)
    description: str = ""
    dimensions: int = 2
    control_inputs: bool = False

    # ------------------------------------------------------------------ queries
    def link_names(self) -> list[str]:
        """Names of all links (bodies then beams)."""
        return list(self.bodies) + list(self.beams)

    def copy(self) -> "Model":
        """A deep copy, safe to modify."""
        return copy.deepcopy(self)

    def validate(self) -> "Model":
        """Check every field and reference; raise :class:`~flexkane.errors.ModelError` on the first
        problem. Returns ``self`` for chaining."""
        from .validate import validate_model

        validate_model(self)
        return self

    def with_values(self, values, *, validate: bool = True) -> "Model":
        """A copy with values set by key path, as ``flexkane run --set KEY=VALUE`` does.

        Parameters
        ----------
        values : mapping of str to value
            Key paths (``"beams.B.EI"``, ``"bodies.RB.points.Q"``, ``"initial.u3"``) or bare names
            (a parameter, else an initial condition) to their new values: numbers, expression
            texts, booleans, lists ``[x, y]`` or tables, as a model file would give them.
        validate : bool
            Validate the copy (:meth:`validate`) before returning it.

        Returns
        -------
        Model
            The copy; ``self`` is unchanged.

        Raises
        ------
        ModelError
            Naming the key of an unknown path or an invalid value.

        Examples
        --------
        >>> stiff = flexkane.builtin_model("falling-beam").with_values({"beams.B.EI": 40, "u3": 2})  # doctest: +SKIP
        """
        from collections.abc import Mapping

        from .paths import set_value

        if not isinstance(values, Mapping):
            raise ModelError("values", "a mapping of key paths to values, e.g. {'beams.B.EI': 20}",
                             type(values).__name__)
        new = self.copy()
        for key, value in values.items():
            if not isinstance(key, str) or not key.strip():
                raise ModelError("values", "key paths as non-empty strings (e.g. 'beams.B.EI')", key)
            set_value(new, key.strip(), copy.deepcopy(value))
        return new.validate() if validate else new

    def with_modes(self, n_modes: int) -> "Model":
        """A copy in which every beam has ``n_modes`` transverse shape functions (a spatial beam:
        ``n_modes`` in each bending plane and of torsion that it has, ``n_modes_y``, ``n_modes_z``,
        ``n_torsion`` > 0).

        Beams whose shape roots were typed explicitly keep them only when their count matches. The
        initial values of the modal coordinates and speeds follow their coordinate (renamed with
        ``naming = "sequential"``, whose numbers shift); those of modes beyond ``n_modes`` are
        dropped (:meth:`initial_beyond_modes` names them, for a note).
        """
        new = self._with_mode_counts(n_modes)
        new.initial, _ = self._initial_with_modes(new)
        return new

    def initial_beyond_modes(self, n_modes: int) -> list[str]:
        """The keys of ``[initial]`` that :meth:`with_modes` drops: the initial values of modal
        coordinates and speeds beyond ``n_modes`` (in the model's order)."""
        return self._initial_with_modes(self._with_mode_counts(n_modes))[1]

    def _initial_with_modes(self, new: "Model") -> tuple[dict, list[str]]:
        """``(initial, dropped)``: this model's initial values renamed to the coordinates of ``new``
        (the same chain with other mode counts), and the keys of those ``new`` does not have. The
        initial values are kept as they are when the chain's coordinates cannot be named (an invalid
        model: its validation reports why)."""
        from .coordinates import coordinate_names

        before, after = self.copy(), new.copy()
        before.initial, after.initial = {}, {}
        try:
            after.validate()
            names = [coordinate_names(before), coordinate_names(after)]
        except ModelError:
            return dict(self.initial), []
        targets = {(c.owner, c.role, c.index): c for c in names[1]}
        renamed: dict = {}          # name in this model -> name in new (None: no such coordinate)
        for c in names[0]:
            target = targets.get((c.owner, c.role, c.index))
            renamed[c.q] = target.q if target is not None else None
            if c.u is not None:
                renamed[c.u] = target.u if target is not None else None
        initial, dropped = {}, []
        for key, value in self.initial.items():
            if renamed.get(key, key) is None:
                dropped.append(key)
            else:
                initial[renamed.get(key, key)] = value
        return initial, dropped

    def _with_mode_counts(self, n_modes: int) -> "Model":
        """A copy with every beam's mode counts set to ``n_modes`` (:meth:`with_modes`), its initial
        values unchanged."""
        from .validate import MAX_ELASTIC_COORDINATES, MAX_MODES

        if isinstance(n_modes, bool) or not isinstance(n_modes, int) or not 1 <= n_modes <= MAX_MODES:
            raise ModelError("n_modes", f"an integer from 1 to {MAX_MODES}", n_modes)
        families = {name: sum(1 for n in (beam.n_modes_y, beam.n_modes_z, beam.n_torsion) if n) or 1
                    for name, beam in self.beams.items()}
        total = n_modes * sum(families.values()) + sum(beam.n_axial or 0 for beam in self.beams.values())
        if total > MAX_ELASTIC_COORDINATES:
            raise ModelError("n_modes", f"at most {MAX_ELASTIC_COORDINATES} shape functions over all beams "
                             "(n_modes + n_axial summed)", n_modes,
                             f"{total} with n_modes {n_modes} on {len(self.beams)} beam(s)")
        new = self.copy()
        for beam in new.beams.values():
            if new.dimensions == 3:       # a spatial beam
                for key, shape in (("n_modes_y", "shape_y"), ("n_modes_z", "shape_z"), ("n_torsion", "torsion_shape")):
                    if not getattr(beam, key):
                        continue
                    setattr(beam, key, n_modes)
                    spec = getattr(beam, shape)
                    if spec is not None and spec.roots is not None and len(spec.roots) != n_modes:
                        raise ModelError(f"beams.{beam.name}.{shape}.roots",
                                         f"{n_modes} roots to match {key} (or a model without typed roots)", spec.roots)
                continue
            beam.n_modes = n_modes
            if beam.shape.roots is not None and len(beam.shape.roots) != n_modes:
                raise ModelError(f"beams.{beam.name}.shape.roots",
                                 f"{n_modes} roots to match n_modes (or a model without typed roots)",
                                 beam.shape.roots)
            if beam.damping and len(beam.damping) != n_modes:
                beam.damping = (list(beam.damping) + [beam.damping[-1]] * n_modes)[:n_modes]
        return new
