"""The Jiang–Tadmor (1998) staggered central scheme in two dimensions (docs/design.md, "Toward
two dimensions"): so far its numpy reference step, the oracle of the compiled kernel to come."""

from conslaw.schemes.jiang_tadmor.reference import JiangTadmorReference

__all__ = ["JiangTadmorReference"]
