"""The switch between compiled (numba) kernels and the pure-numpy reference paths.

A few hot loops (the 3D shape context votes, ...) have a numba kernel next to their numpy code; both give the
same numbers (the tests compare them). The compiled kernel runs when numba is importable and the environment
variable ``VOXPOSE_KERNELS`` is unset or ``numba``; ``VOXPOSE_KERNELS=numpy`` selects the numpy paths (for
comparison, or where numba cannot be installed). The variable is read at each call, so tests can switch it.

Kernels are compiled with ``cache=True`` (the machine code is kept in ``__pycache__`` next to the module, so
only the first process after an install pays the compilation) and ``nogil=True`` (threads run them in
parallel).
"""

import functools
import os

from voxpose.errors import VoxposeError

ENV = "VOXPOSE_KERNELS"
CHOICES = ("numba", "numpy")


@functools.cache
def numba_available() -> bool:
    """Whether numba can be imported (once per process)."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def use_numba() -> bool:
    """True when the compiled kernels should run (module docstring)."""
    choice = os.environ.get(ENV, "numba").strip().lower() or "numba"
    if choice not in CHOICES:
        raise VoxposeError(f"{ENV}={choice!r}: expected one of {', '.join(CHOICES)}")
    return choice == "numba" and numba_available()


def jit(fn):
    """``numba.njit(cache=True, nogil=True)``; the plain function when numba is missing (never called then)."""
    if not numba_available():
        return fn
    import numba

    return numba.njit(cache=True, nogil=True)(fn)
