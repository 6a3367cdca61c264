"""Kane's method for planar chains with flexible links (eqs. 8.10-8.36)."""

from .equations import EquationsOfMotion, derive

__all__ = ["EquationsOfMotion", "derive"]
