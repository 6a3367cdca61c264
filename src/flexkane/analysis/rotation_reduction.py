"""Perturbations of spatial orientations: three rotation coordinates per set of Euler parameters.

A spherical or free joint (``dimensions = 3``) orients its child by four Euler parameters
``e = (e0, e1, e2, e3)`` of unit norm, with three angular speeds ``w`` (along the child joint frame
J_c's axes) and ``e' = 1/2 E(e) w`` (:func:`flexkane.kane.rotation.euler_parameter_rates`). A
perturbation of the orientation about a reference ``e_ref`` is a small turn ``dtheta`` of J_c about
its own axes [rad]::

    e = e_ref (x) (cos(|dtheta|/2), sin(|dtheta|/2) dtheta/|dtheta|)  =  e_ref (x) (1, dtheta/2) + O(dtheta^2),

(``(x)`` the quaternion product), so that to first order

    de = P dtheta,   P = 1/2 E(e_ref)   (4 x 3),        dtheta = P^+ de,   P^+ = 2 E(e_ref)^T   (3 x 4),

``P^+`` the pseudo-inverse of P on the tangent space of the unit sphere (``E^T E = I``, ``E^T e = 0``).
These three coordinates are named ``rx_<joint>``, ``ry_<joint>``, ``rz_<joint>``; every other
coordinate maps to itself. For the whole chain ``dq = T dq_r`` and ``dq_r = T^+ dq``, and the linear
model in ``dq_r`` (as many coordinates as speeds) is::

    K_r = K T,    W_r = T^+ W,    V_r = T^+ (V T - T'),

where ``T' = dT/dt`` along the reference motion (``P' = 1/2 E(e_ref')``, zero at rest): about a
steady spin of the joint with angular velocity ``w0``, ``V_r`` of its block is ``-[w0 x]``
(``dtheta' = dtheta x w0 + dw``), so the linear model of a body spinning about a principal axis has
constant coefficients though its Euler parameters turn.

The translations ``x = (x, y, z)`` of a free joint that spins freely are measured along the turning
frame J_c too: ``dx = C(e_ref) dxi`` (``C`` the direction cosines of J_c in J_p), so that with
``x' = C(e) v``, ``dxi' = dv - w0 x dxi``, again with constant coefficients (in J_p's axes the row
``dx' = C(e_ref(t)) dv`` would turn with the body). They are named ``sx_<joint>, sy_<joint>,
sz_<joint>``; at rest (``w0 = 0``) the translations keep their names and J_p's axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.coordinates import EULER_ROLES

__all__ = ["RotationReduction", "AXES", "euler_matrix", "turn"]

#: Name prefixes of the three rotation coordinates of a joint, about J_c's x, y, z axes.
AXES = ("rx", "ry", "rz")
#: Name prefixes of a freely spinning free joint's translations along J_c's axes.
SHIFTS = ("sx", "sy", "sz")


def direction_cosines(e: np.ndarray) -> np.ndarray:
    """Direction cosines ``C(e)`` (``v_A = C v_B``) of Euler parameters e, shape (3, 3)
    (:func:`flexkane.kane.rotation.euler_parameter_matrix`)."""
    e0, e1, e2, e3 = e
    return np.array([
        [e0 ** 2 + e1 ** 2 - e2 ** 2 - e3 ** 2, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
        [2 * (e1 * e2 + e0 * e3), e0 ** 2 - e1 ** 2 + e2 ** 2 - e3 ** 2, 2 * (e2 * e3 - e0 * e1)],
        [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 ** 2 - e1 ** 2 - e2 ** 2 + e3 ** 2]], dtype=float)


def euler_matrix(e: np.ndarray) -> np.ndarray:
    """``E(e)`` of ``e' = 1/2 E(e) w``, shape (4, 3): ``E(e) w = e (x) (0, w)``."""
    e0, e1, e2, e3 = e
    return np.array([[-e1, -e2, -e3], [e0, -e3, e2], [e3, e0, -e1], [-e2, e1, e0]], dtype=float)


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def turn(e: np.ndarray, dtheta: np.ndarray) -> np.ndarray:
    """Euler parameters ``e (x) exp(dtheta / 2)``: ``e`` turned by ``dtheta`` [rad] about its own axes."""
    angle = float(np.linalg.norm(dtheta))
    if angle == 0.0:
        step = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        step = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * np.asarray(dtheta) / angle])
    turned = _product(np.asarray(e, dtype=float), step)
    return turned / np.linalg.norm(turned)


@dataclass(frozen=True)
class RotationReduction:
    """The map between a chain's coordinates and its independent coordinates (module docstring).

    Attributes
    ----------
    n_full : int
        Number of coordinates q (Euler parameters included).
    blocks : list of (str, list of int, list of int)
        Per joint with Euler parameters: its name, the positions of e0..e3 in q and the positions of
        its three rotation coordinates in the reduced coordinates.
    names : list of str
        Names of the reduced coordinates, length ``n_full - len(blocks)``.
    plain : list of (int, int)
        (position in q, position in the reduced coordinates) of every other coordinate.
    shifts : list of (list of int, list of int, list of int)
        Per freely spinning free joint: the positions of its Euler parameters and of its x, y, z in q
        and of ``sx, sy, sz`` in the reduced coordinates.
    speeds : list of str
        Name of the generalized speed of each reduced coordinate (``rx_J``: ``u_J_wx``), length n: a
        reduced coordinate is dependent in a closed loop when its speed is
        (:func:`flexkane.analysis.reduction.loop_columns`).
    """

    n_full: int
    blocks: list
    names: list
    plain: list
    shifts: list = ()
    speeds: list = ()

    @classmethod
    def of(cls, coordinates: list, q_names: list[str], spinning: str | None = None) -> "RotationReduction | None":
        """The reduction of the coordinates ``q_names`` (names of ``coordinates``, the chain's
        :class:`~flexkane.kane.chain.Coordinate` objects with ``role`` and ``owner``); None when none
        of them is an Euler parameter. ``spinning``: a joint spinning freely (its translations, if
        it is a free joint, are measured along its child frame)."""
        by_name = {c.q.name: c for c in coordinates}
        roles = [by_name[name].role for name in q_names]
        if not any(role in EULER_ROLES for role in roles):
            return None
        angular = {(c.owner, c.role): c.u for c in coordinates if c.role in EULER_ROLES}
        speed = lambda u: u.name if u is not None else ""  # noqa: E731
        blocks, names, plain, seen, speeds = [], [], [], {}, []
        moving: dict = {}
        for k, name in enumerate(q_names):
            c = by_name[name]
            if c.owner == spinning and c.role in ("x", "y", "z"):
                moving.setdefault("rows", []).append(k)
                moving.setdefault("cols", []).append(len(names))
                names.append(f"{SHIFTS['xyz'.index(c.role)]}_{c.owner}")
                speeds.append(speed(c.u))
            elif c.role in EULER_ROLES:
                if c.owner not in seen:
                    seen[c.owner] = (c.owner, [None] * 4, list(range(len(names), len(names) + 3)))
                    blocks.append(seen[c.owner])
                    names += [f"{axis}_{c.owner}" for axis in AXES]
                    speeds += [speed(angular.get((c.owner, role))) for role in EULER_ROLES[1:]]
                seen[c.owner][1][EULER_ROLES.index(c.role)] = k
            else:
                plain.append((k, len(names)))
                names.append(name)
                speeds.append(speed(c.u))
        shifts = [(seen[spinning][1], moving["rows"], moving["cols"])] if moving else []
        return cls(len(q_names), blocks, names, plain, shifts, speeds)

    @property
    def n(self) -> int:
        """Number of reduced coordinates."""
        return len(self.names)

    def tangent(self, q: np.ndarray, rate: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(T, T^+)`` at the configuration q, shapes (n_full, n) and (n, n_full); with ``rate`` =
        ``q'`` along the reference motion, ``(T', T^+')`` instead (zero for every plain coordinate)."""
        derivative = rate is not None     # (T^+' is not used: T^+ T = I gives T^+' T = -T^+ T')
        source = np.asarray(rate if derivative else q, dtype=float)
        T, T_plus = np.zeros((self.n_full, self.n)), np.zeros((self.n, self.n_full))
        if not derivative:
            for k, j in self.plain:
                T[k, j] = T_plus[j, k] = 1.0
        for _, rows, cols in self.blocks:
            E = euler_matrix(source[rows])
            T[np.ix_(rows, cols)] = 0.5 * E
            T_plus[np.ix_(cols, rows)] = 2.0 * E.T
        for euler, rows, cols in self.shifts:
            e = np.asarray(q, dtype=float)[euler]
            if derivative:      # C is quadratic in e: its rate is the central difference exactly
                d = source[euler]
                C = 0.5 * (direction_cosines(e + d) - direction_cosines(e - d))
            else:
                C = direction_cosines(e)
            T[np.ix_(rows, cols)] = C
            T_plus[np.ix_(cols, rows)] = C.T
        return T, T_plus

    def retract(self, q_ref: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The configuration ``q_ref`` moved by the reduced coordinates x: plain coordinates added,
        orientations turned exactly (:func:`turn`), shape (n_full,)."""
        q = np.array(q_ref, dtype=float)
        x = np.asarray(x, dtype=float)
        for k, j in self.plain:
            q[k] = q_ref[k] + x[j]
        for euler, rows, cols in self.shifts:
            q[rows] = q_ref[rows] + direction_cosines(q_ref[euler]) @ x[cols]
        for _, rows, cols in self.blocks:
            q[rows] = turn(q_ref[rows], x[cols])
        return q

    def columns(self, joint: str) -> list[int]:
        """Positions of a joint's three rotation coordinates in the reduced coordinates."""
        return next(cols for name, _, cols in self.blocks if name == joint)

    def wrap(self, q_ref: np.ndarray, evaluators: dict, steady: list[int] = ()) -> dict:
        """Equilibrium evaluators (:func:`flexkane.analysis.equilibrium.check_equilibrium`) in the
        reduced coordinates x about ``q_ref``: ``stiffness`` becomes ``K T`` and ``rates`` ``T^+ q'``,
        but for the columns ``steady`` (a joint spinning freely: its orientation turns at the
        operating point, which is a steady motion, not a rest). With closed loops (``constraints``
        and ``constraint_jacobian`` among the evaluators) also ``Phi`` and ``Phi_q T``."""
        at = lambda x: self.retract(q_ref, x)   # noqa: E731
        keep = np.ones(self.n)
        keep[list(steady)] = 0.0
        wrapped = {"forcing": lambda x: evaluators["forcing"](at(x)),
                   "mass": lambda x: evaluators["mass"](at(x)),
                   "stiffness": lambda x: evaluators["stiffness"](at(x)) @ self.tangent(at(x))[0],
                   "rates": lambda x: keep * (self.tangent(at(x))[1] @ evaluators["rates"](at(x)))}
        if evaluators.get("constraints") is not None:    # closed loops: Phi and Phi_q T
            wrapped["constraints"] = lambda x: evaluators["constraints"](at(x))
            wrapped["constraint_jacobian"] = \
                lambda x: evaluators["constraint_jacobian"](at(x)) @ self.tangent(at(x))[0]
        return wrapped

    def settle(self, q_start: np.ndarray, evaluators: dict, steady: list[int] = (), iterations: int = 100) -> np.ndarray:
        """A configuration near ``q_start`` where the forcing vanishes, by Gauss-Newton steps in the
        reduced coordinates re-centred at every step (where ``K T`` is the exact Jacobian), each the
        least-norm step (so that neutral directions, such as turns about the vertical, are not
        wandered along) halved until the forcing decreases; shape (n_full,). The caller checks it.
        With closed loops (``constraints`` among the evaluators) the residual is the forcing and the
        loops' gaps together, ``(f, w Phi)`` with the Jacobian ``(-K T, w Phi_q T)``, ``w`` balancing
        forces [N] and gaps [m] as :func:`~flexkane.analysis.equilibrium.find_equilibrium` does."""
        q = self.normalize(q_start)
        zero = np.zeros(self.n)
        loops = evaluators.get("constraints") is not None
        weight = 1.0
        if loops:
            first = self.wrap(q, evaluators, steady)
            K, G = first["stiffness"](zero), first["constraint_jacobian"](zero)
            if np.abs(G).max() > 0 and np.abs(K).max() > 0:
                weight = float(np.abs(K).max() / np.abs(G).max())

        def residual(wrapped, x):
            f = wrapped["forcing"](x)
            return np.concatenate([f, weight * wrapped["constraints"](x)]) if loops else f

        for _ in range(iterations):
            wrapped = self.wrap(q, evaluators, steady)
            f = residual(wrapped, zero)
            size = float(np.linalg.norm(f))
            if size == 0.0 or not np.isfinite(size):
                break
            J = -wrapped["stiffness"](zero)
            if loops:
                J = np.vstack([J, weight * wrapped["constraint_jacobian"](zero)])
            step = np.linalg.lstsq(J, -f, rcond=1e-10)[0]
            fraction = 1.0
            while fraction > 1e-6:
                trial = self.retract(q, fraction * step)
                if float(np.linalg.norm(residual(wrapped, fraction * step))) < size:
                    break
                fraction /= 2
            else:
                break
            q = trial
            if float(np.max(np.abs(fraction * step), initial=0.0)) < 1e-15:
                break
        return q

    def reference_rows(self) -> np.ndarray:
        """Whether each coordinate of q is held by the reference of a reduced block (Euler parameters,
        a spinning joint's translations) rather than mapped to itself, shape (n_full,)."""
        held = np.zeros(self.n_full, dtype=bool)
        for _, rows, _ in [*self.blocks, *self.shifts]:
            held[rows] = True
        return held

    def normalize(self, q: np.ndarray) -> np.ndarray:
        """q with each joint's Euler parameters scaled to unit norm."""
        q = np.array(q, dtype=float)
        for _, rows, _ in self.blocks:
            q[rows] = q[rows] / np.linalg.norm(q[rows])
        return q
