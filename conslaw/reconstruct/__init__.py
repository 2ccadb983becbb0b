"""Slope reconstruction from cell averages: TVD limiters and WENO."""

from conslaw.reconstruct.base import Reconstructor, builtin_reconstructors

__all__ = ["Reconstructor", "builtin_reconstructors"]
