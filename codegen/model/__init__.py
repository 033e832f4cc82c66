"""What a model file builds a mechanism from (docs/models.md): ``codegen.model.mechanism``.

The public name of the model's building blocks; the implementation is
``codegen.compiler.model``. Importing this loads none of the shipped models (those load by
name, ``codegen.compiler.model.load``) and nothing of the runtime.
"""
from __future__ import annotations

from ..compiler.model.checks import ModelError
from .mechanism import (TIME, Body, Coordinate, Damper, Mechanism, Parameter, PointForce,
                        Requirement, Sketch, Spring, Torque, distance, parameter)

__all__ = ["TIME", "Body", "Coordinate", "Damper", "Mechanism", "ModelError", "Parameter",
           "PointForce", "Requirement", "Sketch", "Spring", "Torque", "distance", "parameter"]
