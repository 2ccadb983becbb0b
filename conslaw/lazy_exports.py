"""Names of a package imported from its submodules on first use (PEP 562, a module's
``__getattr__``), so that importing one submodule does not import the others and what they
need (matplotlib, pyogrio, scipy.stats)."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(package: str, homes: Mapping[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``package`` giving each name of ``homes`` (name ->
    submodule) from its submodule, imported when the name is first asked for.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    homes : mapping of str to str
        Exported name -> the submodule (relative to ``package``) that defines it.

    Returns
    -------
    callable
        To assign to the package's ``__getattr__``.
    """

    def getattr_(name: str) -> Any:
        if name not in homes:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.{homes[name]}"), name)

    return getattr_
