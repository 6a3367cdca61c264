"""Model description: the parts of a chain, model files, validation and field symbols."""

from .as_spatial import as_spatial
from .model import NAMING_STYLES, Model
from .parts import (Beam, DistributedLoad, Driver, Gravity, Joint, Load, LoopConstraint, Orientation, PointSpring,
                    RigidBody, ShapeSpec, Simulation)
from .toml_io import dumps_model, load_model, loads_model, save_model

__all__ = ["Model", "NAMING_STYLES", "RigidBody", "Beam", "ShapeSpec", "Joint", "Driver", "Gravity",
           "Load", "DistributedLoad", "Orientation", "as_spatial", "LoopConstraint", "PointSpring", "Simulation",
           "load_model", "loads_model", "dumps_model", "save_model"]
