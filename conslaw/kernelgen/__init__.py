"""Kernel toolkit: compiled modules generated from a template and bindings, cached on disk.

It knows no model and no scheme: a template is a Python module with a binding block, bindings
are module-level compiled functions, constants are compile-time values (docs/design.md,
"Compiled kernels"). :mod:`conslaw.kernelgen.stack` gives kernels small arrays on the stack.
"""

from conslaw.kernelgen.generation import (
    cache_dir,
    compile_lock,
    compiled_before,
    dependency_sources,
    generate,
    import_path,
)

__all__ = [
    "cache_dir",
    "compile_lock",
    "compiled_before",
    "dependency_sources",
    "generate",
    "import_path",
]
