"""(c) ``flexible-arm`` in flexkane and in Exudyn, at matched accuracy of the tip deflection.

The same system in both: a hub (J_hub) on a revolute joint driven by the torque pulse
``T0 sin(2 pi t / t1)`` for t < t1, a uniform link (L, EI, rho) clamped to the hub at r_hub, a
payload (m_tip, J_tip) welded at the tip, t in [0, 1.5] s.

* flexkane: assumed modes with ``geometric_stiffening = true`` (the foreshortening of the beam
  axis, the kinematics closest to Exudyn's), compiled, ``method="auto"``; the shape functions of
  the built-in model (clamped-free, eq. 8.4) or those of a cantilever carrying the payload
  (``clamped-free-tip-mass``), which converge faster for this arm.
* Exudyn: ``ObjectANCFCable2D`` elements (Euler-Bernoulli, geometrically exact, axial stiffness
  EA = 1e5 N), the hub and the payload ``ObjectRigidBody2D``, the cable's end nodes clamped to
  them by ``ObjectJointGeneric`` (x, y and the rotation), the hub on ``ObjectJointRevolute2D``, the
  torque a ``LoadTorqueVector`` with a Python user function; implicit generalized-alpha solver with
  fixed step h (Exudyn's explicit solvers do not accept these joints).

Accuracy of each run: ``max_t |d - d_ref| / max_t |d_ref|`` for the tip deflection d in the hub
frame, against the converged solution of the same tool (flexkane: 10 clamped-free modes at
rtol = 1e-11;
Exudyn: 16 elements at h = 5e-5 s). For each accuracy target the cheapest setting of each tool that
reaches it is compared (wall time of the integration only; model building excluded). The two
converged solutions are also compared with each other, at the built-in torque and at a tenth of it.

Usage: ``python benchmarks/exudyn_arm.py``.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

import flexkane
from flexkane.model.parts import ShapeSpec
from flexkane.numerics import integrate

from _common import best_time, build, fmt_time, relative_error, tip_function

TARGETS = (1e-2, 2e-3)
ARM = dict(J_hub=0.05, m_hub=2.0, r_hub=0.05, L=1.0, EI=12.0, rho=0.6, m_tip=0.25, J_tip=5e-4,
           T0=2.0, t1=0.6, t_end=1.5, dt_out=0.005)
EA = 1e5  # axial stiffness of the cable [N]: inextensible in practice (strains below 1e-5)


def exudyn_arm(elements: int, h: float, T0: float = ARM["T0"]):
    """Build and solve the arm in Exudyn; return ``(t, d, wall)`` with d the tip deflection."""
    import exudyn as exu
    from exudyn.itemInterface import (LoadTorqueVector, MarkerBodyPosition, MarkerBodyRigid,
                                      MarkerNodeRigid, NodeRigidBody2D, ObjectANCFCable2D,
                                      ObjectGround, ObjectJointGeneric, ObjectJointRevolute2D,
                                      ObjectRigidBody2D, SensorNode)
    from exudyn.beams import GenerateStraightLineANCFCable2D

    a = ARM
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    n_hub = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, 0, 0]))
    hub = mbs.AddObject(ObjectRigidBody2D(nodeNumber=n_hub, mass=a["m_hub"], inertia=a["J_hub"]))
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[
        mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground)),
        mbs.AddMarker(MarkerBodyPosition(bodyNumber=hub))]))
    t1 = a["t1"]

    def torque(mbs_, t, load):
        return [0.0, 0.0, T0 * math.sin(2.0 * math.pi * t / t1) if t < t1 else 0.0]

    mbs.AddLoad(LoadTorqueVector(markerNumber=mbs.AddMarker(MarkerBodyRigid(bodyNumber=hub)),
                                 loadVectorUserFunction=torque))
    cable = ObjectANCFCable2D(physicsMassPerLength=a["rho"], physicsBendingStiffness=a["EI"],
                              physicsAxialStiffness=EA)
    r, L = a["r_hub"], a["L"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        nodes = GenerateStraightLineANCFCable2D(mbs, [r, 0, 0], [r + L, 0, 0], elements, cable,
                                                fixedConstraintsNode0=None,
                                                fixedConstraintsNode1=None)[0]
    clamp = mbs.AddMarker(MarkerBodyRigid(bodyNumber=hub, localPosition=[r, 0, 0]))
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[clamp, mbs.AddMarker(MarkerNodeRigid(nodeNumber=nodes[0]))],
                                     constrainedAxes=[1, 1, 0, 0, 0, 1]))
    n_tip = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[r + L, 0, 0]))
    tip = mbs.AddObject(ObjectRigidBody2D(nodeNumber=n_tip, mass=a["m_tip"], inertia=a["J_tip"]))
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[mbs.AddMarker(MarkerBodyRigid(bodyNumber=tip)),
                                                    mbs.AddMarker(MarkerNodeRigid(nodeNumber=nodes[-1]))],
                                     constrainedAxes=[1, 1, 0, 0, 0, 1]))
    s_tip = mbs.AddSensor(SensorNode(nodeNumber=n_tip, writeToFile=False, storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Position))
    s_hub = mbs.AddSensor(SensorNode(nodeNumber=n_hub, writeToFile=False, storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = a["t_end"]
    settings.timeIntegration.numberOfSteps = int(round(a["t_end"] / h))
    settings.timeIntegration.verboseMode = 0
    settings.timeIntegration.newton.useModifiedNewton = True
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = a["dt_out"]
    settings.show.statistics = False
    settings.show.computationTime = False
    tic = time.perf_counter()
    mbs.SolveDynamic(settings)
    wall = time.perf_counter() - tic
    tip_xy = mbs.GetSensorStoredData(s_tip)
    phi = mbs.GetSensorStoredData(s_hub)[:, 3]
    xc, yc = r * np.cos(phi), r * np.sin(phi)
    d = -(tip_xy[:, 1] - xc) * np.sin(phi) + (tip_xy[:, 2] - yc) * np.cos(phi)
    return tip_xy[:, 0], d, wall


def _flexkane_arm(n: int, T0: float = ARM["T0"], tip_mass_modes: bool = False):
    model = flexkane.builtin_model("flexible-arm").with_modes(n)
    model.beams["link"].geometric_stiffening = True
    if tip_mass_modes:  # the cantilever's own modes with the payload at its tip
        model.beams["link"].shape = ShapeSpec("clamped-free-tip-mass", options={
            "mass_ratio": ARM["m_tip"] / (ARM["rho"] * ARM["L"]),
            "inertia_ratio": ARM["J_tip"] / (ARM["rho"] * ARM["L"] ** 3)})
    model.parameters["T0"] = T0
    return build(model, ("dop853", "radau"))


def _cheapest(rows, target):
    ok = [r for r in rows if r["error"] <= target]
    return min(ok, key=lambda r: r["wall"]) if ok else None


def run() -> dict:
    print("(c) flexible-arm: flexkane (assumed modes, geometric stiffening) against Exudyn "
          "(ANCF cable elements, generalized-alpha)")
    grid = np.linspace(0.0, ARM["t_end"], int(round(ARM["t_end"] / ARM["dt_out"])) + 1)
    ours = []
    reference = _flexkane_arm(10)
    tip10 = tip_function(reference.eom, "link")
    ref = integrate(reference.module, reference.y0, grid, reference.p, rtol=1e-11, atol=1e-13,
                    method="dop853")
    d_ref = tip10(ref.y, reference.p)
    for tip_mass_modes, modes in ((False, (2, 3, 4, 6)), (True, (2, 3, 4))):
        family = "clamped-free-tip-mass" if tip_mass_modes else "clamped-free"
        for n in modes:
            built = _flexkane_arm(n, tip_mass_modes=tip_mass_modes)
            tip = tip_function(built.eom, "link")
            for rtol in (1e-3, 1e-5):
                result = integrate(built.module, built.y0, grid, built.p, rtol=rtol,
                                   atol=rtol * 1e-2)
                wall = best_time(lambda: integrate(built.module, built.y0, grid, built.p,
                                                   rtol=rtol, atol=rtol * 1e-2))
                ours.append({"setting": f"{n} {family} modes, rtol {rtol:g} ({result.method})",
                             "wall": wall, "error": relative_error(tip(result.y, built.p), d_ref)})
    t_ref, e_ref, e_ref_wall = exudyn_arm(16, 5e-5)
    theirs = []
    for elements in (2, 4, 8):
        for h in (2e-3, 1e-3, 5e-4, 2.5e-4):
            walls, d = [], None
            for _ in range(2):
                _, d, wall = exudyn_arm(elements, h)
                walls.append(wall)
            theirs.append({"setting": f"{elements} elements, h = {h:g} s", "wall": min(walls),
                           "error": relative_error(d, e_ref)})
    model_difference = relative_error(e_ref, d_ref)
    small = _flexkane_arm(10, ARM["T0"] / 10)
    small_ref = integrate(small.module, small.y0, grid, small.p, rtol=1e-11, atol=1e-13,
                          method="dop853")
    _, e_small, _ = exudyn_arm(16, 5e-5, ARM["T0"] / 10)
    small_difference = relative_error(e_small, tip_function(small.eom, "link")(small_ref.y, small.p))
    print(f"  converged solutions (flexkane 10 modes, Exudyn 16 elements at h = 5e-5 s, "
          f"{fmt_time(e_ref_wall)}): max tip deflection {np.abs(d_ref).max() * 1e3:.2f} mm; they "
          f"differ by {model_difference:.1e} of it (by {small_difference:.1e} with a tenth of the "
          "torque: the difference is the geometric nonlinearity that the second-order "
          "foreshortening of assumed modes leaves out)")
    matches = []
    for target in TARGETS:
        b = _cheapest(theirs, target)
        for family in ("clamped-free", "clamped-free-tip-mass"):
            a = _cheapest([r for r in ours if f" {family} modes" in r["setting"]], target)
            match = {"target": target, "family": family, "flexkane": a, "exudyn": b,
                     "ratio": b["wall"] / a["wall"] if a and b else None}
            matches.append(match)
            if a and b:
                print(f"  tip error <= {target:g}: flexkane {fmt_time(a['wall'])} ({a['setting']}, "
                      f"error {a['error']:.1e}); Exudyn {fmt_time(b['wall'])} ({b['setting']}, "
                      f"error {b['error']:.1e}): {match['ratio']:.0f}x faster", flush=True)
            else:
                print(f"  tip error <= {target:g} ({family}): not reached by "
                      f"{'flexkane' if a is None else 'Exudyn'} in the settings tried")
    return {"flexkane": ours, "exudyn": theirs, "matches": matches,
            "model_difference": model_difference, "model_difference_small": small_difference,
            "max_tip": float(np.abs(d_ref).max()), "exudyn_reference_wall": e_ref_wall}


if __name__ == "__main__":
    run()
