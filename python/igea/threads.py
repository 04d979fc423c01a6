"""igea.blas_threads(n): OpenBLAS's thread count for a block of code.

libigea never changes process state (its calls run in the BLAS threads the
host chose); a program that runs many igea calls in threads of its own
(concurrent.futures, igea.montecarlo with threads > 1) should give BLAS one
thread meanwhile, or the two pools oversubscribe the cores:

    with igea.blas_threads(1):
        results = list(pool.map(job, flights))

With threadpoolctl installed, every BLAS library of the process is limited
(numpy's and scipy's too); without it, the OpenBLAS that libigea is linked
with, through its openblas_set_num_threads. The previous counts are
restored on leaving the block, also on an exception.
"""
import contextlib
import ctypes

from . import _lib


def _openblas():
    """(get, set) of the OpenBLAS that libigea uses, or None."""
    try:
        get, set_ = _lib.lib.openblas_get_num_threads, _lib.lib.openblas_set_num_threads
    except AttributeError:
        return None
    get.restype, get.argtypes = ctypes.c_int, []
    set_.restype, set_.argtypes = None, [ctypes.c_int]
    return get, set_


@contextlib.contextmanager
def blas_threads(n):
    """Within the block, BLAS runs n threads (an int >= 1); see the module."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"igea.blas_threads: n: expected an int >= 1, got {n!r}")
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        threadpool_limits = None
    if threadpool_limits is not None:
        with threadpool_limits(limits=n, user_api="blas"):
            yield
        return
    ob = _openblas()
    if ob is None:  # another BLAS: nothing to set
        yield
        return
    get, set_ = ob
    old = get()
    set_(n)
    try:
        yield
    finally:
        set_(old)
