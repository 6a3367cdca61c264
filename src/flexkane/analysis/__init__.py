"""Linearization and modal analysis of whole chains.

The stages, one public function each::

    linear = flexkane.analysis.linearize(model, about="equilibrium")   # M du' + C du + K dq = B dr
    modal = flexkane.analysis.modal_analysis(linear)                   # frequencies, zeta, shapes
    A, B = linear.state_space(); linear.save_mat("arm.mat")
    system = linear.to_control()          # python-control StateSpace, named states, inputs, outputs
    diagram = flexkane.analysis.campbell_diagram(model, spins)         # frequencies against spin
    study = flexkane.analysis.convergence_study(model, [1, 2, 4, 8])   # frequencies against n

Modules: :mod:`.prepare` (inputs and steady spin), :mod:`.equilibrium` (operating points),
:mod:`.linearization` (symbolic Jacobians),
:mod:`.rotation_reduction` (rotation coordinates of spatial orientations), :mod:`.linear_model`
(numeric matrices, export),
:mod:`.eigen` (modes), :mod:`.campbell`, :mod:`.convergence`, :mod:`.mode_plot` (drawings).
"""

from .campbell import CampbellDiagram, campbell_diagram
from .convergence import ConvergenceStudy, convergence_study
from .eigen import ModalAnalysis, Mode, modal_analysis
from .equilibrium import NoEquilibriumError
from .linear_model import LinearModel, linear_outputs, load_control
from .linearization import ABOUT, Linearization, linearize
from .mode_plot import plot_mode_shapes
from .prepare import InputChannel

__all__ = ["ABOUT", "Linearization", "linearize", "LinearModel", "linear_outputs", "load_control", "InputChannel", "NoEquilibriumError",
           "ModalAnalysis", "Mode", "modal_analysis", "CampbellDiagram", "campbell_diagram",
           "ConvergenceStudy", "convergence_study", "plot_mode_shapes"]
