"""Numerical schemes behind one interface (:class:`conslaw.schemes.base.Scheme`)."""

from conslaw.schemes.base import AdvanceResult, BoundarySpec, Scheme

__all__ = ["AdvanceResult", "BoundarySpec", "Scheme"]
