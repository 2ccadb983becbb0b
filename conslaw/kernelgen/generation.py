"""Generation of compiled kernels from templates.

numba caches compiled code on disk only for functions defined at module level in a real source file,
not for closures or for functions taking other compiled functions as arguments. So a kernel that is
generic over the model, the reconstructor and the boundary conditions is produced by writing a small
module per combination: the template's text with its binding block replaced by imports of the chosen
module-level functions. The file name carries a hash of the template and of the source files of
the compiled functions the kernel can reach (:func:`dependency_sources`), so editing the physics
invalidates the cache and editing anything else does not.

Cache folder: ``$CONSLAW_CACHE_DIR``, else the user's cache folder (:func:`cache_dir`); a
temporary folder if neither is writable.
"""

from __future__ import annotations

import ast
import contextlib
import getpass
import hashlib
import importlib
import importlib.util
import numbers
import os
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from types import CodeType, ModuleType
from typing import Any

import numba
import numpy as np
from numba.core.caching import Cache, _CacheLocator

from conslaw.errors import KernelCacheError

_BEGIN = "# --- bindings ---"
_END = "# --- end bindings ---"
_loaded: dict[str, ModuleType] = {}
#: The name of the module each request of this process got (:func:`_request_key`): a second
#: scheme of the same kind (an ensemble's next member) skips reading and hashing the sources.
_generated: dict[tuple[Any, ...], str] = {}
#: One thread at a time writes and imports a generated module (and fills ``_loaded``).
_lock = threading.RLock()
#: One thread at a time parses a template (CPython 3.11's ``ast`` keeps a recursion counter that
#: concurrent parses corrupt: "AST constructor recursion depth mismatch").
_parse_lock = threading.Lock()


def cache_dir() -> Path:
    """Folder of the generated kernel modules (created if needed).

    ``CONSLAW_CACHE_DIR`` if set to a non-empty value (a KernelCacheError if it cannot be used:
    it is never silently replaced; an empty value counts as not set, as for ``XDG_CACHE_HOME``),
    else the user's cache folder (``platformdirs``: ``$XDG_CACHE_HOME/conslaw/kernels`` or
    ``~/.cache/conslaw/kernels`` on Linux, ``~/Library/Caches/conslaw/kernels`` on macOS,
    ``%LOCALAPPDATA%\\conslaw\\Cache\\kernels`` on Windows), else a folder in the system's
    temporary folder.
    """
    chosen = os.environ.get("CONSLAW_CACHE_DIR")
    if chosen:
        try:
            return _usable(Path(chosen))
        except OSError as error:
            raise KernelCacheError(
                f"CONSLAW_CACHE_DIR='{chosen}' cannot hold compiled kernels: "
                f"{error.strerror or error}; point it to a writable folder"
            ) from None
    import platformdirs

    candidates = [
        Path(platformdirs.user_cache_dir("conslaw", appauthor=False)) / "kernels",
        Path(tempfile.gettempdir()) / f"conslaw-kernels-{_user()}",
    ]
    for folder in candidates:
        try:
            return _usable(folder)
        except OSError:
            continue
    raise KernelCacheError(
        "no writable folder for conslaw's compiled kernels; set CONSLAW_CACHE_DIR"
    )


def _user() -> str:
    """The user's name for a folder of their own in the shared temporary folder."""
    try:
        return getpass.getuser()
    except (KeyError, OSError):  # no name for this user id (a container)
        return str(os.getpid())


def _usable(folder: Path) -> Path:
    """``folder``, made if needed, once a file could be written into it (else an OSError)."""
    folder.mkdir(parents=True, exist_ok=True)
    probe = folder / f".probe-{os.getpid()}-{threading.get_ident()}"
    probe.write_text("")
    probe.unlink()
    return folder


def numba_cache_folder(module_file: Path) -> Path:
    """The folder in which numba keeps the cache of the functions of ``module_file``, as its
    cache locators choose it: under ``NUMBA_CACHE_DIR`` (``numba.config.CACHE_DIR``) in a
    folder named for the module's folder when that is set, else ``__pycache__`` beside the
    module (the kernel folder is writable: :func:`cache_dir`)."""
    numba_folder = getattr(numba.config, "CACHE_DIR", "")  # set at run time: no stub knows it
    if numba_folder:
        return Path(numba_folder) / _CacheLocator.get_suitable_cache_subpath(str(module_file))
    return module_file.parent / "__pycache__"


def compiled_before(module: ModuleType, function: str) -> bool:
    """Whether numba's cache of a generated ``module`` (:func:`numba_cache_folder`) holds
    ``function`` compiled (for some argument types): False means its first call compiles.
    Always True without the JIT."""
    if getattr(numba.config, "DISABLE_JIT", False):
        return True
    folder = numba_cache_folder(Path(module.__file__ or ""))
    return any(folder.glob(f"{module.__name__}.{function}-*.nbi"))


def import_path(function: Callable[..., Any]) -> tuple[str, str]:
    """``(module, name)`` under which a compiled function can be imported.

    Raises
    ------
    TypeError
        If the function is not reachable as a module-level attribute (a closure, a lambda, ...).
    """
    python_function = getattr(function, "py_func", function)
    module_name = python_function.__module__
    name = python_function.__name__
    module = importlib.import_module(module_name)
    if getattr(module, name, None) is not function:
        raise TypeError(
            f"{module_name}.{name} must be a module-level numba function (njit) to be compiled "
            "into a kernel"
        )
    return module_name, name


def _defining_file(value: Any) -> str | None:
    """The source file that defines a compiled function, intrinsic or overload, if any."""
    for attribute in ("py_func", "_defn", "_definition_func"):
        inner = getattr(value, attribute, None)
        if inner is not None:
            code = getattr(inner, "__code__", None)
            return code.co_filename if code is not None else None
    return None


def _names_used(code: CodeType) -> set[str]:
    """Global and attribute names a code object (and the code objects nested in it) uses."""
    names = set(code.co_names)
    for constant in code.co_consts:
        if isinstance(constant, CodeType):
            names |= _names_used(constant)
    return names


_PLAIN = (bool, int, float, complex, str, bytes, tuple, type(None))


def _reachable(roots: Mapping[str, Any]) -> Iterator[tuple[str, Any]]:
    """Every value the compiled code of ``roots`` can reach, with a label: the roots, and for
    each compiled function the globals it uses and the attributes of the modules it uses."""
    seen: set[int] = set()
    pending: list[tuple[str, Any]] = list(roots.items())
    while pending:
        label, value = pending.pop()
        if id(value) in seen:
            continue
        seen.add(id(value))
        yield label, value
        function = getattr(value, "py_func", None)
        if isinstance(value, _PLAIN) or _defining_file(value) is None or function is None:
            continue
        namespace = function.__globals__
        used = _names_used(function.__code__)
        for name in sorted(used & namespace.keys()):
            target = namespace[name]
            if isinstance(target, ModuleType):
                pending.extend(
                    (f"{target.__name__}.{attribute}", getattr(target, attribute))
                    for attribute in sorted(used)
                    if hasattr(target, attribute)
                )
            else:
                pending.append((f"{function.__module__}.{name}", target))


def dependency_sources(roots: Mapping[str, Any]) -> list[str]:
    """What the compiled code reachable from ``roots`` depends on: the text of every source file
    that defines a compiled function it can call (following the globals each function uses, and
    the attributes of modules it uses), and the value of every plain constant it reads.

    numba freezes a global constant into the compiled code and checks only the calling file's
    time stamp before it loads cached code, so these are what a kernel's cache key must cover;
    the folder around a bound module is not (appending to ``conslaw/cli.py`` recompiles nothing).
    """
    files: set[str] = set()
    constants: list[str] = []
    for label, value in _reachable(roots):
        if isinstance(value, _PLAIN):
            constants.append(f"{label}={value!r}")
            continue
        file = _defining_file(value)
        if file is not None:
            files.add(file)
    texts = []
    for file in sorted(files):
        try:
            texts.append(f"{package_path(Path(file))}\0{Path(file).read_text()}")
        except OSError:
            texts.append(file)
    return texts + sorted(constants)


def package_path(file: Path) -> str:
    """``file``'s path from the folder that holds its top-level package
    (``conslaw/schemes/nessyahu_tadmor/kernel_template.py``; a file outside a package: its
    name). Kernel keys use it instead of the absolute path, so that two installations of the
    same code (a source checkout and site-packages, or two virtual environments) share their
    compiled kernels."""
    parts = [file.name]
    folder = file.parent
    while (folder / "__init__.py").exists() and folder.parent != folder:
        parts.append(folder.name)
        folder = folder.parent
    return "/".join(reversed(parts))


def _template_imports(text: str) -> dict[str, Any]:
    """The objects a template imports at module level with ``from ... import`` (outside its
    binding block), by name; numpy, numba and llvmlite are versioned by numba's own cache."""
    head, _, rest = text.partition(_BEGIN)
    _, _, tail = rest.partition(_END)
    objects: dict[str, Any] = {}
    with _parse_lock:  # CPython 3.11's ast is not thread-safe ("recursion depth mismatch")
        tree = ast.parse(head + tail)
    for node in tree.body:
        if not isinstance(node, ast.ImportFrom) or not node.module or node.level != 0:
            continue
        if node.module.split(".")[0] in ("numpy", "numba", "llvmlite"):
            continue
        module = importlib.import_module(node.module)
        for alias in node.names:
            objects[f"{node.module}.{alias.name}"] = getattr(module, alias.name, None)
    return objects


def _literal(value: object) -> str:
    """A constant as Python source: a numpy scalar as the Python number or bool it holds
    (numpy 2 writes ``numpy.True_`` as ``np.True_``, a name the generated module lacks)."""
    if isinstance(value, bool | np.bool_):
        return repr(bool(value))
    if isinstance(value, numbers.Integral):
        return repr(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value))
    raise TypeError(f"a kernel constant must be a bool, int or float, got {value!r}")


def _binding_block(block: str, statements: list[str]) -> str:
    """The binding block rewritten with ``statements`` in exactly as many lines as the template's
    block has, so that every line after it keeps the template's line number (tracebacks and
    numba's messages name the template's own lines)."""
    room = block.count("\n") - 1
    if room < 1:
        raise ValueError("a template's binding block needs at least one line between its markers")
    per_line = max(1, -(-len(statements) // room))
    rows = ["; ".join(statements[i : i + per_line]) for i in range(0, len(statements), per_line)]
    rows += [""] * (room - len(rows))
    return "\n".join([_BEGIN, *rows, _END])


def _prune(folder: Path, family: str, keep: str) -> None:
    """Remove the generated modules of ``family`` other than ``keep`` and the one used last
    before it, with numba's cache files of them: the same template and bindings generated from
    earlier versions of the code. The one used last stays so that two versions in use at once
    (two virtual environments, or checkouts compared with each other) do not remove each other's
    kernels at every switch."""
    others = sorted(
        (path for path in folder.glob(f"{family}_*.py") if path.stem != keep),
        key=_last_use,
        reverse=True,
    )
    kept = {keep, *(path.stem for path in others[:1])}
    for suffix in ("py", "lock"):
        for path in folder.glob(f"{family}_*.{suffix}"):
            if path.stem not in kept:
                path.unlink(missing_ok=True)
    # numba's cache files of the family's other modules (also of modules already gone)
    for cached in numba_cache_folder(folder / f"{keep}.py").glob(f"{family}_*"):
        if cached.name.split(".", 1)[0] not in kept:
            cached.unlink(missing_ok=True)


def _last_use(module_file: Path) -> float:
    """When a generated module was last imported: the time stamp of its lock file (touched at
    every import; the module itself is not touched, numba checks its time stamp), else of the
    module."""
    for path in (module_file.with_suffix(".lock"), module_file):
        try:
            return path.stat().st_mtime
        except OSError:
            continue
    return 0.0


def generate(
    template: str | Path,
    bindings: Mapping[str, Callable[..., Any]],
    constants: Mapping[str, bool | int | float] | None = None,
    imports: Mapping[str, ModuleType] | None = None,
) -> ModuleType:
    """Write (once) and import the module of ``template`` with ``bindings`` in place.

    Parameters
    ----------
    template : str or Path
        The template file (a Python module with a binding block).
    bindings : mapping
        Placeholder name -> module-level compiled function.
    constants : mapping, optional
        Module-level constants (compile-time for numba: dead branches are removed).
    imports : mapping, optional
        Template module name -> generated module: the template's ``from NAME import ...``
        statements import from the generated module instead (a template that continues another
        calls the other's functions, compiled once with the other's bindings and constants).

    Notes
    -----
    Every line of the generated module outside the binding block is the template's line of the
    same number. The file name is ``conslaw_kernel_<folder>_<template>_<identity>_<digest>``: the
    identity hashes what was asked for (template, bindings, constants, imports), the digest all the
    compiled code depends on (:func:`dependency_sources`). A module of the same identity and
    another digest is stale; it is removed, with numba's cache files of it, when the new one is
    written.
    """
    imports = dict(imports or {})
    path = Path(template).resolve()
    jit = "nojit" if getattr(numba.config, "DISABLE_JIT", False) else "jit"
    asked = _request_key(path, bindings, constants, imports, jit)
    with _lock:
        known = _generated.get(asked) if asked is not None else None
        if known is not None and known in _loaded:
            return _loaded[known]
    module = _generate(path, bindings, constants, imports, jit)
    if asked is not None:
        with _lock:
            _generated[asked] = module.__name__
    return module


def _request_key(
    path: Path,
    bindings: Mapping[str, Callable[..., Any]],
    constants: Mapping[str, bool | int | float] | None,
    imports: Mapping[str, ModuleType],
    jit: str,
) -> tuple[Any, ...] | None:
    """What a call of :func:`generate` asked for, as a key of this process's memo (the bound
    functions themselves, not their names: a function redefined in this process is another
    request); None if a binding cannot be a key."""
    key = (
        str(path),
        jit,
        tuple(sorted(bindings.items(), key=lambda item: item[0])),
        tuple(sorted((constants or {}).items())),
        tuple(sorted((name, module.__name__) for name, module in imports.items())),
    )
    try:
        hash(key)
    except TypeError:
        return None
    return key


def _generate(
    path: Path,
    bindings: Mapping[str, Callable[..., Any]],
    constants: Mapping[str, bool | int | float] | None,
    imports: Mapping[str, ModuleType],
    jit: str,
) -> ModuleType:
    """:func:`generate` without the memo: the module's text, its name from the text and the
    sources it depends on, then the module written (once) and imported."""
    text = path.read_text()
    for name, module in sorted(imports.items()):
        text = text.replace(f"from {name} import", f"from {module.__name__} import")
    statements = []
    roots: dict[str, Any] = _template_imports(text)
    for placeholder, function in sorted(bindings.items()):
        module_name, name = import_path(function)
        statements.append(f"from {module_name} import {name} as {placeholder}")
        roots[placeholder] = function
    statements += [f"{key} = {_literal(value)}" for key, value in sorted((constants or {}).items())]
    if _BEGIN in text:
        head, rest = text.split(_BEGIN, 1)
        block, tail = rest.split(_END, 1)
        body = head + _binding_block(_BEGIN + block + _END, statements) + tail
    elif statements:
        raise ValueError(f"{path.name} has no binding block ({_BEGIN!r} ... {_END!r})")
    else:
        body = text
    # An imported generated module enters by its own identity, so the same template with other
    # imported kernels is another family (and is not pruned as a stale copy of this one).
    imported = [f"{name}={module.__kernel_family__}" for name, module in sorted(imports.items())]
    # Without the JIT (NUMBA_DISABLE_JIT) nothing is compiled and the dependencies are unknown: a
    # family of its own (``jit``), so that it never prunes the compiled modules.
    identity = hashlib.sha256("\0".join([package_path(path), jit, *statements, *imported]).encode())
    digest = hashlib.sha256("\0".join([body, *dependency_sources(roots)]).encode())
    family = f"conslaw_kernel_{path.parent.name}_{path.stem}_{identity.hexdigest()[:12]}"
    module_name = f"{family}_{digest.hexdigest()[:16]}"
    with _lock:
        if module_name in _loaded:
            return _loaded[module_name]
        folder = cache_dir()
        with _folder_lock(folder):
            return _write_and_import(folder, family, module_name, body)


@contextlib.contextmanager
def _folder_lock(folder: Path) -> Iterator[None]:
    """Other processes using the cache folder wait while this one writes, imports and prunes
    (an advisory lock on ``folder/.lock``)."""
    with _file_lock(folder / ".lock"):
        yield


@contextlib.contextmanager
def compile_lock(module: ModuleType) -> Iterator[None]:
    """Hold while making the first calls of a generated ``module``, which compile it: another
    process that needs the same module waits here, and its own first calls then load the
    compiled code from numba's cache instead of compiling it a second time (parallel test
    workers, ensemble members, ``conslaw warm``). An advisory lock on ``<module>.lock`` beside
    the module; nothing waits without the JIT."""
    if getattr(numba.config, "DISABLE_JIT", False) or not module.__file__:
        yield
        return
    with _file_lock(Path(module.__file__).with_suffix(".lock")):
        yield


@contextlib.contextmanager
def _file_lock(path: Path) -> Iterator[None]:
    """An exclusive advisory lock on ``path`` (created if needed) between processes and between
    threads (each holder opens the file itself); without ``fcntl`` (not POSIX), no lock."""
    try:
        import fcntl
    except ImportError:  # not on POSIX
        yield
        return
    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def _write_and_import(folder: Path, family: str, module_name: str, body: str) -> ModuleType:
    """Write the module (if not there or not the same bytes: a damaged copy is rewritten), prune
    the stale modules of its family and import it; numba's cache of it repairs itself
    (:class:`_RepairingCache`)."""
    target = folder / f"{module_name}.py"
    try:
        present = target.read_bytes() if target.exists() else None
    except OSError:
        present = None
    if present != body.encode():
        temporary = target.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
        try:
            temporary.write_bytes(body.encode())  # UTF-8 and "\n" whatever the platform
            os.replace(temporary, target)
        except OSError as error:
            temporary.unlink(missing_ok=True)
            raise KernelCacheError(
                f"cannot write compiled kernels into '{folder}': {error.strerror or error}; "
                "free some space or set CONSLAW_CACHE_DIR to another folder"
            ) from None
        _prune(folder, family, keep=module_name)
    with contextlib.suppress(OSError):  # the last use, for _prune (not needed to run)
        target.with_suffix(".lock").touch()
    spec = importlib.util.spec_from_file_location(module_name, target)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    # numba's cache re-imports the module by name when it loads a cached function.
    sys.modules[module_name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[module_name]
        raise
    setattr(module, "__kernel_family__", family)  # noqa: B010 (an attribute of our own)
    for _, value in _reachable(vars(module)):
        cache = getattr(value, "_cache", None)
        if isinstance(cache, Cache):
            value._cache = _RepairingCache(cache)
    _loaded[module_name] = module
    return module


class _RepairingCache:
    """numba's on-disk cache of one compiled function, made robust to damaged files: an entry
    that cannot be loaded (a truncated or garbled index or data file) is deleted and the function
    compiled again, which writes a good entry; a failure to save (a full disk) leaves the
    function compiled in memory only. Everything else is numba's ``Cache``."""

    def __init__(self, cache: Cache) -> None:
        self._cache = cache

    def __getattr__(self, name: str) -> Any:
        return getattr(self._cache, name)

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        try:
            return self._cache.load_overload(sig, target_context)
        except Exception:  # whatever a damaged file raises: pickle, EOF, ...
            self._remove_files()
            return None

    def save_overload(self, sig: Any, data: Any) -> None:
        try:
            self._cache.save_overload(sig, data)
        except Exception:  # a full disk, or a damaged index met again
            self._remove_files()

    def _remove_files(self) -> None:
        """Delete this function's index and data files."""
        cache_file = getattr(self._cache, "_cache_file", None)
        index_path = getattr(cache_file, "_index_path", None)
        if index_path is None:  # another numba: leave its files alone
            return
        index = Path(index_path)
        index.unlink(missing_ok=True)
        for data in index.parent.glob(f"{index.stem}.*.nbc"):
            data.unlink(missing_ok=True)
