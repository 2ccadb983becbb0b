"""The Jiang–Tadmor (1998) staggered central scheme in two dimensions (docs/design.md, "Toward
two dimensions"): the compiled scheme (:class:`JiangTadmor`), the same with the depth's margins
tracked (:class:`JiangTadmorTracked`, docs/design.md, "Margins in two dimensions") and its numpy
reference step (:class:`JiangTadmorReference`), the oracle of the kernel's tests."""

from conslaw.schemes.jiang_tadmor.reference import JiangTadmorReference
from conslaw.schemes.jiang_tadmor.scheme import JiangTadmor
from conslaw.schemes.jiang_tadmor.tracked import JiangTadmorTracked

__all__ = ["JiangTadmor", "JiangTadmorReference", "JiangTadmorTracked"]
