"""The Jiang–Tadmor (1998) staggered central scheme in two dimensions (docs/design.md, "Toward
two dimensions"): the compiled scheme (:class:`JiangTadmor`) and its numpy reference step
(:class:`JiangTadmorReference`), the oracle of the kernel's tests."""

from conslaw.schemes.jiang_tadmor.reference import JiangTadmorReference
from conslaw.schemes.jiang_tadmor.scheme import JiangTadmor

__all__ = ["JiangTadmor", "JiangTadmorReference"]
