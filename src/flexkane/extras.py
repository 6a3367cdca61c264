"""Optional dependencies: the extras of the package and a clear message when one is missing.

The base install carries what every run needs. Sweeps need Dask and pyarrow (``flexkane[sweep]``),
MP4 movies need the ffmpeg of imageio-ffmpeg (``flexkane[video]``), ``Results.to_dataframe`` needs
pandas (``flexkane[dataframe]``), python-control state-space models need python-control
(``flexkane[control]``); ``flexkane[all]`` installs them all.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import FlexkaneError

__all__ = ["MissingExtraError", "require", "EXTRAS"]

#: Extra of each optional top-level module, and what it is for.
EXTRAS = {"dask": ("sweep", "parameter sweeps"), "distributed": ("sweep", "parameter sweeps"),
          "pyarrow": ("sweep", "sweep tables (sweep.parquet)"),
          "imageio_ffmpeg": ("video", "MP4 movies"), "pandas": ("dataframe", "Results.to_dataframe"),
          "control": ("control", "python-control state-space models (LinearModel.to_control)")}


class MissingExtraError(FlexkaneError, ImportError):
    """An optional package is not installed; the message names the package and the extra to install.

    Parameters
    ----------
    package : str
        Name of the missing package as pip knows it.
    extra : str
        The extra of flexkane that installs it.
    purpose : str
        What needs it.
    """

    def __init__(self, package: str, extra: str, purpose: str):
        self.package = package
        self.extra = extra
        super().__init__(f"the package {package!r}, needed for {purpose}, is not installed: "
                         f"pip install 'flexkane[{extra}]' (or pip install '{package}')")


def require(module: str, package: str | None = None) -> ModuleType:
    """Import an optional module, or raise :class:`MissingExtraError` naming its extra.

    Parameters
    ----------
    module : str
        Module to import, e.g. ``"pyarrow.parquet"``; its top-level name must be in :data:`EXTRAS`.
    package : str, optional
        Name of the package on PyPI (the top-level module name, with ``_`` as ``-``, by default).

    Returns
    -------
    module
    """
    top = module.split(".")[0]
    extra, purpose = EXTRAS[top]
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        if exc.name is not None and exc.name.split(".")[0] != top:
            raise  # the optional package is there but one of its own dependencies is broken
        raise MissingExtraError(package or top.replace("_", "-"), extra, purpose) from None
