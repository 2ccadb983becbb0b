"""The Lagrangian moving grid of Savage & Hutter (1989) (:mod:`.scheme`)."""

from conslaw.schemes.lagrangian.scheme import LagrangianScheme

__all__ = ["LagrangianScheme"]
