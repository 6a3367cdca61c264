"""Parameter sweeps: derive once per structure, run thousands of variants, lose nothing.

A sweep varies model values by key path (``beams.B.EI``, ``initial.q3``, ``g``) over a grid or
random draws, runs every variant (here, on all cores through a Dask LocalCluster, or on an existing
Dask cluster) and keeps one table row per variant: its values, its status and summary metrics::

    from flexkane.sweep import SweepSpec, Vary, run_sweep, read_table

    spec = SweepSpec(vary=(Vary.parse("beams.B.EI=20:80:4"), Vary.parse("initial.q3=0.5,1.0")),
                     t_end=0.5, dt_out=0.001)
    outcome = run_sweep("falling-beam-exact", spec, out="out/ei-sweep")
    table = read_table("out/ei-sweep")          # pyarrow.Table; sweep.csv holds the same rows

Re-running the same sweep into the same directory computes only the variants it lacks.
"""

from .metrics import energy_error, summary_metrics
from .plot import column_units, default_metric, plot_metric
from .runner import SweepInterrupted, SweepOutcome, describe_outcome, run_sweep
from .spec import SAMPLINGS, SweepSpec, Vary, sweep_spec_from_toml
from .table import read_table
from .variants import RunSettings, Variant, make_variants

__all__ = ["run_sweep", "SweepSpec", "Vary", "SweepOutcome", "SweepInterrupted", "read_table", "plot_metric",
           "sweep_spec_from_toml", "make_variants", "Variant", "RunSettings", "summary_metrics", "energy_error",
           "default_metric", "describe_outcome", "SAMPLINGS", "column_units"]
