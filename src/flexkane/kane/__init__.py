"""Kane's method for planar chains with flexible links (eqs. 8.10-8.36) and for spatial ones, their
generalization to three dimensions (the ``spatial_*`` modules)."""

from .equations import EquationsOfMotion, derive

__all__ = ["EquationsOfMotion", "derive"]
