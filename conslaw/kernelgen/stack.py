"""Small scratch arrays on the stack, for the per-cell state vectors of the compiled kernels.

The model's pointwise functions take and fill small arrays (``q``, ``aux``, ``out``). Allocated
with ``np.empty`` these live on the heap: every element goes through memory, and the compiler
cannot keep them in registers or vectorise the loop over the cells. :func:`local_vector` and
:func:`local_matrix` give arrays of a size known at compile time in the calling function's stack
frame (no allocation at run time, no reference counting). Once the pointwise functions are inlined
and the loops over the variables unrolled, LLVM turns every element into a register, so a kernel
written against the array interface runs as if it had been written with scalars.

Only for use inside compiled functions; the size must be a compile-time constant (a literal or a
module-level integer) and the array must not outlive the function that made it.
"""

from __future__ import annotations

from typing import Any

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

_FLOAT = types.float64
_ITEMSIZE = 8


def _stack_array(context: Any, builder: Any, shape: tuple[int, ...]) -> Any:
    """An array struct over ``prod(shape)`` doubles allocated in the entry block of the
    function being compiled (so a call inside a loop does not grow the stack)."""
    array_type = types.Array(_FLOAT, len(shape), "C")
    size = 1
    for extent in shape:
        size *= extent
    intp = context.get_value_type(types.intp)
    data = cgutils.alloca_once(
        builder, context.get_value_type(_FLOAT), size=ir.Constant(intp, max(size, 1))
    )
    strides: list[int] = []
    stride = _ITEMSIZE
    for extent in reversed(shape):
        strides.insert(0, stride)
        stride *= extent
    array = make_array(array_type)(context, builder)
    populate_array(
        array,
        data=data,
        shape=[ir.Constant(intp, extent) for extent in shape],
        strides=[ir.Constant(intp, s) for s in strides],
        itemsize=ir.Constant(intp, _ITEMSIZE),
        meminfo=None,
    )
    return array._getvalue()


@intrinsic
def local_vector(typingctx: Any, size: Any) -> Any:
    """``np.empty(size)`` (float64) on the stack; ``size`` a compile-time integer."""
    if not isinstance(size, types.IntegerLiteral):
        return None
    extent = int(size.literal_value)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return _stack_array(context, builder, (extent,))

    return types.Array(_FLOAT, 1, "C")(size), codegen


@intrinsic
def local_matrix(typingctx: Any, size: Any) -> Any:
    """``np.empty((size, size))`` (float64) on the stack; ``size`` a compile-time integer."""
    if not isinstance(size, types.IntegerLiteral):
        return None
    extent = int(size.literal_value)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return _stack_array(context, builder, (extent, extent))

    return types.Array(_FLOAT, 2, "C")(size), codegen
