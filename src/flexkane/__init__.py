"""flexkane: dynamics of planar kinematic chains with continuous flexible links, by Kane's method."""

__version__ = "0.1.0"
