"""numba compilation options shared by the package's kernels.

``@numba.njit(**NJIT_OPTIONS)`` decorates every kernel of :mod:`mbm.special` and of
the paper and splitting modules of :mod:`mbm.approximants`.
"""

__all__ = ["NJIT_OPTIONS", "unmanaged"]

# cache: compiled kernels persist in __pycache__, so only the first run compiles.
# error_model="numpy": a float division by zero gives ±inf/nan instead of raising
# ZeroDivisionError inside a compiled loop; kernels report failure by status code or
# NaN, never by an exception (the cn form (2.17) needs R = 0 → Abar = inf, the special
# functions their poles; no kernel result changes for a non-zero divisor).
NJIT_OPTIONS = {"cache": True, "error_model": "numpy"}


from numba import types  # noqa: E402
from numba.core import cgutils  # noqa: E402
from numba.extending import intrinsic  # noqa: E402


@intrinsic
def unmanaged(typingctx, arr):
    """A view of the 1-D C-contiguous array ``arr`` that holds no reference to its memory.

    numba counts the references of every array view it binds, passes or returns, with an
    atomic add and subtract each (measured: a fifth of a window's time in the loop's
    per-window bookkeeping).  The view returned here has no memory owner, so those
    counts are skipped; the caller keeps ``arr`` alive for as long as the view is used.
    """
    if not (isinstance(arr, types.Array) and arr.ndim == 1 and arr.layout == "C"):
        return None
    sig = arr(arr)

    def codegen(context, builder, signature, args):
        view = cgutils.create_struct_proxy(signature.return_type)(context, builder, value=args[0])
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        view.parent = cgutils.get_null_value(view.parent.type)
        return view._getvalue()

    return sig, codegen
