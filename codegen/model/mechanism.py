"""The building blocks of a model file: ``from codegen.model.mechanism import Body, ...``.

The same classes as ``codegen.compiler.model.mechanism``, where they are defined.
"""
from __future__ import annotations

from ..compiler.model.mechanism import (TIME, Body, Coordinate, Damper, Mechanism, Parameter,
                                        PointForce, Requirement, Sketch, Spring, Torque,
                                        distance, parameter)

__all__ = ["TIME", "Body", "Coordinate", "Damper", "Mechanism", "Parameter", "PointForce",
           "Requirement", "Sketch", "Spring", "Torque", "distance", "parameter"]
