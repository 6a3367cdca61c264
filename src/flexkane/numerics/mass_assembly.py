"""The mass matrix of a long planar chain summed from twists and composite bodies by one compiled loop.

Written out entry by entry, ``M`` of a chain of k links costs the generated code a few operations
per pair of speeds and per pair of a speed and a link (the twist of every speed at the frame of
every deeper speed): its size, and Numba's compile time (about 1.5 ms of CPU per operation), grow
like k^2. :class:`flexkane.kane.inertia.MassAssembly` gives the same ``M`` as data: each speed's
twist where it starts to move links rigidly (*sources*), each link's composite rigid-body
properties and its frame's pose in its parent, each beam mode's *wrench*, and the beams' own
modal-mass entries. The generated right-hand side evaluates those (a number of statements that
grows with the links) into four small arrays and calls :func:`assemble_mass_matrix`, written once
here and compiled once per installation; which pairs to sum is structure, kept as integer tables
(module constants of the generated module, :func:`assembly_tables`).

The loop brings everything to N (axes of N, moments about its origin), as the hand-written
recursive yardstick does, so that a pair costs one dot product:

    pose of a link in N:  P_b = P_parent o X_b                 (angle and origin composed)
    twist in N:           t = (R A + W k x (-r), W)           (velocity of the point at N's origin)
    composite in N:       S_N = R S + m r,  J_N = J + 2 r . (R S) + m |r|^2
    momentum of a source: h_s = I_F t_s = (m A_x - S_y W, m A_y + S_x W, -S_y A_x + S_x A_y + J W)
    wrench of a mode:     h_r = (R c_xy, c_w + r x R c_xy)
    M_rs += t_r . h_s     (r at the link of s or inward of it; a beam mode's h_r with the sources
                           that move its beam rigidly)

the planar equations of :mod:`flexkane.kane.inertia` (same terms, another frame and order of
summation: the numbers agree to round-off).

A spatial chain's assembly (:mod:`flexkane.kane.spatial_inertia`) is summed in the links' own
frames instead, as the written-out matrix is (:func:`assemble_spatial_mass_matrix`): each source's
twist ``t = (A, W)`` is carried out link by link to the deeper links where it pairs, with the
rotation ``Lambda`` and offset ``s`` of each link's frame in its parent's,

    t_child = (Lambda^T (A + W x s), Lambda^T W),
    momentum of a source: h_s = I_F t_s = (m A + W x S, S x A + J W)   (composite about F)
    wrench of a mode:     h_r = (c_v, c_w)                          (at the beam's frame)
    M_rs += t_r(F) . h_s,

so that its ``M`` is the written-out one term by term whatever the state (the Euler parameters of a
spherical or free joint, whose norm drifts in an integration, enter both through the same
``Lambda``). A transport costs about 39 operations; a chain of k links carries about k^2 / 2
twists, which the loop does at run time while the generated code grows with k.
"""

from __future__ import annotations

import hashlib
import inspect
from dataclasses import dataclass

import numpy as np
from numba import njit

from flexkane.numerics.checked_numba_cache import guard_namespace

__all__ = ["AssemblyTables", "assemble_mass_matrix", "assemble_spatial_mass_matrix", "assembly_tables",
           "source_digest", "work_size"]

# Operations of one step of each loop (counted as in codegen: + - * /).
_POSE_OPERATIONS = 12
_TWIST_OPERATIONS = 8
_COMPOSITE_OPERATIONS = 14
_MOMENTUM_OPERATIONS = 12
_PAIR_OPERATIONS = 6
# The same, of the spatial loop.
_SPATIAL_TRANSPORT_OPERATIONS = 39
_SPATIAL_MOMENTUM_OPERATIONS = 36
_SPATIAL_PAIR_OPERATIONS = 12


@njit(cache=True, error_model="numpy")
def assemble_mass_matrix(M, X, I, T, C, work, poses, momenta, pair_starts, pair_sources, pair_rows,
                         pair_columns):
    """Add the composite-body and wrench terms to the upper triangle of ``M`` (in place).

    Parameters
    ----------
    M : ndarray (nu, nu)
        Mass matrix, holding the explicit entries (zero elsewhere); upper triangle written.
    X : ndarray (n_links, 4)
        ``(cos, sin, d_x, d_y)`` of each link's frame in its parent's (in N for a link on the
        ground) [-, -, m, m].
    I : ndarray (n_links, 4)
        Composite ``(m, S_x, S_y, J)`` about each link's frame, its axes [kg, kg m, kg m, kg m^2].
    T : ndarray (n_sources, 3)
        Twists ``(A_x, A_y, W)`` of the sources at their link's frame, its axes.
    C : ndarray (n_wrenches, 3)
        Wrenches of beam modes at their beam's frame, its axes.
    work : ndarray (:func:`work_size`,)
        Scratch space.
    poses : ndarray (n, 2) of uint64
        ``(link, parent)`` in tree order (parent = link: on the ground): the links whose pose in N
        is needed.
    momenta : ndarray (n_momenta, 2) of uint64
        ``(index, link)``: first every source (``index`` a row of T, in order), whose momentum
        ``I t`` is formed, then the wrenches used (``index`` a row of C).
    pair_starts : ndarray (n_momenta + 1,) of uint64
        The pairs of momentum ``n`` are ``pair_starts[n]`` to ``pair_starts[n + 1]``.
    pair_sources, pair_rows, pair_columns : ndarray (n_pairs,) of uint64
        Per pair, the source and the entry of M: ``M[row, column] += t_source . h_momentum``.
    """
    P = work                       # poses in N, 4 per link, then the twists in N, 3 per source
    g0 = 4 * X.shape[0]
    for n in range(poses.shape[0]):
        b, a = poses[n, 0], poses[n, 1]
        pb, pa = 4 * b, 4 * a
        if a == b:                 # on the ground
            P[pb], P[pb + 1], P[pb + 2], P[pb + 3] = X[b, 0], X[b, 1], X[b, 2], X[b, 3]
        else:
            c, s = P[pa], P[pa + 1]
            P[pb] = c * X[b, 0] - s * X[b, 1]
            P[pb + 1] = s * X[b, 0] + c * X[b, 1]
            P[pb + 2] = P[pa + 2] + c * X[b, 2] - s * X[b, 3]
            P[pb + 3] = P[pa + 3] + s * X[b, 2] + c * X[b, 3]
    n_sources = T.shape[0]
    for k in range(n_sources):     # twists in N: velocity of the point at N's origin
        pb, gk = 4 * momenta[k, 1], g0 + 3 * k
        c, s, x, y = P[pb], P[pb + 1], P[pb + 2], P[pb + 3]
        w = T[k, 2]
        P[gk] = c * T[k, 0] - s * T[k, 1] + w * y
        P[gk + 1] = s * T[k, 0] + c * T[k, 1] - w * x
        P[gk + 2] = w
    for n in range(momenta.shape[0]):
        k, b = momenta[n, 0], momenta[n, 1]
        pb = 4 * b
        c, s, x, y = P[pb], P[pb + 1], P[pb + 2], P[pb + 3]
        if n < n_sources:          # I_N t of a source, with the composite moved to N
            gk = g0 + 3 * k
            ax, ay, w = P[gk], P[gk + 1], P[gk + 2]
            m = I[b, 0]
            rsx = c * I[b, 1] - s * I[b, 2]
            rsy = s * I[b, 1] + c * I[b, 2]
            sx = rsx + m * x
            sy = rsy + m * y
            j = I[b, 3] + 2.0 * (x * rsx + y * rsy) + m * (x * x + y * y)
            h0 = m * ax - sy * w
            h1 = m * ay + sx * w
            h2 = sx * ay - sy * ax + j * w
        else:                      # a beam mode's wrench, moved to N
            h0 = c * C[k, 0] - s * C[k, 1]
            h1 = s * C[k, 0] + c * C[k, 1]
            h2 = C[k, 2] + x * h1 - y * h0
        for e in range(pair_starts[n], pair_starts[n + 1]):
            g = g0 + 3 * pair_sources[e]
            M[pair_rows[e], pair_columns[e]] += P[g] * h0 + P[g + 1] * h1 + P[g + 2] * h2


@njit(cache=True, error_model="numpy")
def assemble_spatial_mass_matrix(M, X, I, T, C, work, transports, momenta, pair_starts, pair_slots,
                                 pair_rows, pair_columns):
    """Add the composite-body and wrench terms of a spatial chain to the upper triangle of ``M``
    (in place; module docstring).

    Parameters
    ----------
    M : ndarray (nu, nu)
        Mass matrix, holding the explicit entries (zero elsewhere); upper triangle written.
    X : ndarray (n_links, 12)
        Each link frame's orientation ``Lambda`` in its parent's, row by row (``v_parent =
        Lambda v_link``), then its origin ``s`` there [-, m] (rows of links on the ground unread).
    I : ndarray (n_links, 10)
        Composite ``(m, S_x, S_y, S_z, J_xx, J_xy, J_xz, J_yy, J_yz, J_zz)`` about each link's
        frame, its axes [kg, kg m, kg m^2].
    T : ndarray (n_sources, 6)
        Twists ``(A, W)`` of the sources at their link's frame, its axes [m/s, rad/s per speed].
    C : ndarray (n_wrenches, 6)
        Wrenches ``(c_v, c_w)`` of beam modes at their beam's frame, its axes.
    work : ndarray (6 n_slots,)
        Scratch space: the twists, the sources' own (slots 0 to n_sources - 1), then those carried.
    transports : ndarray (n, 3) of uint64
        ``(slot, from slot, link)``: the twist of a slot carried into ``link``'s frame from its
        parent's, in order (a slot after the one it is carried from).
    momenta : ndarray (n_momenta, 2) of uint64
        ``(index, link)``: first every source (``index`` its row of T and its slot), whose momentum
        ``I t`` is formed, then the wrenches used (``index`` a row of C).
    pair_starts : ndarray (n_momenta + 1,) of uint64
        The pairs of momentum ``n`` are ``pair_starts[n]`` to ``pair_starts[n + 1]``.
    pair_slots, pair_rows, pair_columns : ndarray (n_pairs,) of uint64
        Per pair, the slot of a twist at the momentum's link and the entry of M:
        ``M[row, column] += t_slot . h_momentum``.
    """
    W = work
    n_sources = T.shape[0]
    for k in range(n_sources):
        for c in range(6):
            W[6 * k + c] = T[k, c]
    for n in range(transports.shape[0]):
        to, fr, b = 6 * transports[n, 0], 6 * transports[n, 1], transports[n, 2]
        w0, w1, w2 = W[fr + 3], W[fr + 4], W[fr + 5]
        sx, sy, sz = X[b, 9], X[b, 10], X[b, 11]
        v0 = W[fr] + w1 * sz - w2 * sy        # A + W x s
        v1 = W[fr + 1] + w2 * sx - w0 * sz
        v2 = W[fr + 2] + w0 * sy - w1 * sx
        W[to] = X[b, 0] * v0 + X[b, 3] * v1 + X[b, 6] * v2
        W[to + 1] = X[b, 1] * v0 + X[b, 4] * v1 + X[b, 7] * v2
        W[to + 2] = X[b, 2] * v0 + X[b, 5] * v1 + X[b, 8] * v2
        W[to + 3] = X[b, 0] * w0 + X[b, 3] * w1 + X[b, 6] * w2
        W[to + 4] = X[b, 1] * w0 + X[b, 4] * w1 + X[b, 7] * w2
        W[to + 5] = X[b, 2] * w0 + X[b, 5] * w1 + X[b, 8] * w2
    for n in range(momenta.shape[0]):
        k, b = momenta[n, 0], momenta[n, 1]
        if n < n_sources:          # I_F t of a source, at its link F
            a0, a1, a2, w0, w1, w2 = T[k, 0], T[k, 1], T[k, 2], T[k, 3], T[k, 4], T[k, 5]
            m, s0, s1, s2 = I[b, 0], I[b, 1], I[b, 2], I[b, 3]
            h0 = m * a0 + w1 * s2 - w2 * s1
            h1 = m * a1 + w2 * s0 - w0 * s2
            h2 = m * a2 + w0 * s1 - w1 * s0
            h3 = s1 * a2 - s2 * a1 + I[b, 4] * w0 + I[b, 5] * w1 + I[b, 6] * w2
            h4 = s2 * a0 - s0 * a2 + I[b, 5] * w0 + I[b, 7] * w1 + I[b, 8] * w2
            h5 = s0 * a1 - s1 * a0 + I[b, 6] * w0 + I[b, 8] * w1 + I[b, 9] * w2
        else:                      # a beam mode's wrench, at its beam's frame
            h0, h1, h2, h3, h4, h5 = C[k, 0], C[k, 1], C[k, 2], C[k, 3], C[k, 4], C[k, 5]
        for e in range(pair_starts[n], pair_starts[n + 1]):
            g = 6 * pair_slots[e]
            M[pair_rows[e], pair_columns[e]] += (W[g] * h0 + W[g + 1] * h1 + W[g + 2] * h2
                                                 + W[g + 3] * h3 + W[g + 4] * h4 + W[g + 5] * h5)


@dataclass
class AssemblyTables:
    """What the generated code of one assembly evaluates, and the loop's integer tables.

    Attributes
    ----------
    offsets : list of int
        Links whose row of ``X`` is read (every link whose pose in N is needed).
    composites : list of int
        Links whose row of ``I`` is read.
    sources : list of int
        Indices into ``assembly.sources`` (row of ``T`` = position in this list).
    wrenches : list of int
        Indices into ``assembly.wrenches`` of the wrenches used (row of ``C`` = position).
    poses, momenta, pair_starts, pair_sources, pair_rows, pair_columns : ndarray
        The tables of :func:`assemble_mass_matrix` (of a spatial chain's assembly: ``poses`` is
        the table ``transports`` of :func:`assemble_spatial_mass_matrix` and ``pair_sources`` its
        ``pair_slots``).
    operations : int
        Floating-point operations of one call of the loop.
    work : int
        Length of the loop's scratch array.
    """

    offsets: list
    composites: list
    sources: list
    wrenches: list
    poses: np.ndarray
    momenta: np.ndarray
    pair_starts: np.ndarray
    pair_sources: np.ndarray
    pair_rows: np.ndarray
    pair_columns: np.ndarray
    operations: int
    work: int


def assembly_tables(assembly) -> AssemblyTables:
    """The tables of ``assembly`` (:class:`flexkane.kane.inertia.MassAssembly`), deterministic.

    Every source forms its momentum at its link F; a source at F or at a link inward of F (on the
    path to the ground) pairs with it, once per unordered pair at the same link. A beam mode's
    wrench pairs with the sources at its beam or inward of it (those move the beam rigidly). Of a
    spatial chain, the twist of each source at each link where it pairs is a slot, carried from
    the link's parent (``transports``, parents first).
    """
    parent = assembly.parent
    sources = assembly.sources

    def inward(b):   # b and the links on its path to the ground
        out = []
        while b >= 0:
            out.append(b)
            b = parent[b]
        return out

    at_link: dict = {}
    for k, (_, b, _) in enumerate(sources):
        at_link.setdefault(b, []).append(k)
    momenta, pairs = [], []
    for k2, (s, f, _) in enumerate(sources):
        h = len(momenta)
        momenta.append((k2, f))
        for a in inward(f):
            for k in at_link.get(a, ()):
                if a == f and k > k2:
                    continue
                r = sources[k][0]
                times = 2 if (r == s and k != k2) else 1
                pairs += [(k, h, min(r, s), max(r, s))] * times
    used_wrenches = []
    for w, (r, b, _) in enumerate(assembly.wrenches):
        partners = [k for a in inward(b) for k in at_link.get(a, ())]
        if not partners:
            continue
        h = len(momenta)
        momenta.append((len(used_wrenches), b))
        used_wrenches.append(w)
        for k in partners:
            s = sources[k][0]
            pairs.append((k, h, min(r, s), max(r, s)))
    needed = {b for _, b in momenta}
    composites = sorted({f for _, f, _ in sources})
    as_table = lambda rows, width: np.array(rows, dtype=np.uint64).reshape(len(rows), width)  # noqa: E731
    unsigned = lambda values: np.array(values, dtype=np.uint64)  # noqa: E731
    n_sources = len(sources)
    if assembly.dimensions == 3:   # twists carried out link by link: slots (assemble_spatial_mass_matrix)
        slots: dict = {(k, b): k for k, (_, b, _) in enumerate(sources)}
        transports: list = []

        def slot(k, b):
            if (k, b) not in slots:
                before = slot(k, parent[b])
                slots[(k, b)] = n_sources + len(transports)
                transports.append((slots[(k, b)], before, b))
            return slots[(k, b)]

        pairs = [(slot(k, momenta[h][1]), h, i, j) for k, h, i, j in pairs]
        posed = sorted({b for _, _, b in transports})
        poses = as_table(transports, 3)
        operations = (_SPATIAL_TRANSPORT_OPERATIONS * len(transports) + _SPATIAL_MOMENTUM_OPERATIONS * n_sources
                      + _SPATIAL_PAIR_OPERATIONS * len(pairs))
        work = 6 * (n_sources + len(transports))
    else:
        posed = sorted({a for b in needed for a in inward(b)})     # tree order: parents first
        poses = as_table([(b, b if parent[b] < 0 else parent[b]) for b in posed], 2)
        operations = (_POSE_OPERATIONS * len(posed) + (_TWIST_OPERATIONS + _MOMENTUM_OPERATIONS) * n_sources
                      + _COMPOSITE_OPERATIONS * n_sources + 8 * len(used_wrenches)
                      + _PAIR_OPERATIONS * len(pairs))
        work = work_size(max([*posed, *composites, -1]) + 1, n_sources)
    starts = [0] * (len(momenta) + 1)
    for _, h, _, _ in pairs:
        starts[h + 1] += 1
    for n in range(len(momenta)):
        starts[n + 1] += starts[n]
    return AssemblyTables(posed, composites, list(range(len(sources))),
                          used_wrenches, poses,
                          as_table(momenta, 2), unsigned(starts), unsigned([k for k, _, _, _ in pairs]),
                          unsigned([i for _, _, i, _ in pairs]), unsigned([j for _, _, _, j in pairs]),
                          operations, work)


def work_size(n_links: int, n_sources: int) -> int:
    """Length of the scratch array of :func:`assemble_mass_matrix`."""
    return n_links * 4 + n_sources * 3


def source_digest() -> str:
    """Digest of this module's source: generated modules that call the loop name it, so that a
    change of the loop gives them a new cache key (their machine code includes the loop's)."""
    import sys

    return hashlib.sha256(inspect.getsource(sys.modules[__name__]).encode("utf-8")).hexdigest()[:16]


guard_namespace(globals())   # their files in Numba's cache are checked before loading
