"""Layer 1: mechanisms as data."""
from . import doughty
from .mechanism import TIME, Body, Coordinate, Damper, Mechanism, Parameter, PointForce, Spring

__all__ = ["TIME", "Body", "Coordinate", "Damper", "Mechanism", "Parameter", "PointForce",
           "Spring", "doughty"]
