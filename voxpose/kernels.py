"""The switch between compiled (numba) kernels and the pure-numpy reference paths.

A few hot loops (carving: ``voxels.carve_kernels``; the basis voxels: ``voxels.surface_kernels``; the body frame's
resampling: ``descriptors.body_frame_kernels``; the 3D shape context votes: ``descriptors.lut_kernels``; the root
fit's climb: ``apply.root_fit_kernels``; the MPPCA's posterior in its fit, in ``voxpose features`` and in predict:
``features.mppca_kernels``; the silhouette contour's farthest-point sampling: ``descriptors.contour_kernels``) have
a numba kernel next to their numpy code; both give the same numbers (the tests compare them; the MPPCA's to
rounding). The compiled kernel runs when numba is importable and the environment
variable ``VOXPOSE_KERNELS`` is unset or ``numba``; ``VOXPOSE_KERNELS=numpy`` selects the numpy paths (for
comparison, or where numba cannot be installed). The variable is read at each call, so tests can switch it.

Kernels are compiled with ``cache=True`` (the machine code is kept in ``__pycache__`` next to the module, so
only the first process after an install pays the compilation) and ``nogil=True`` (threads run them in
parallel). numba itself is imported at the first kernel call, not with voxpose: importing it costs 0.2 - 0.3 s
of CPU, which processes that run no kernel (or ``VOXPOSE_KERNELS=numpy``) should not pay.

Start-up cost per process (CPU time, measured three times each on the 2-core VM under load, nice 15): the
first call after an install or an edit of a kernel module compiles it, 1.75 - 1.86 s for the carving kernels and
1.16 - 1.19 s for the 3D shape context's. From the cache, the first call costs 0.34 - 0.36 s in a process that
carves (numba's import included) and 0.44 - 0.51 s in one that only describes (import, cached code, and the
folded table with its check), against 0.01 s on the numpy paths. The kernels save about 1.9 ms (carving) and
2.9 ms (shape contexts) per frame in ``benchmarks/bench_predict.py``, so a job breaks even at about 160 - 185
frames: the default motions' jobs (175 - 418 frames) gain from nothing to 0.7 s each, longer motions more.
"""

import functools
import importlib.util
import os
import sys
import threading

from voxpose.errors import VoxposeError

ENV = "VOXPOSE_KERNELS"
CHOICES = ("numba", "numpy")
_pending: dict = {}  # module name -> its kernels not compiled yet
_lock = threading.Lock()


@functools.cache
def numba_available() -> bool:
    """Whether numba is installed (found without importing it)."""
    try:
        return importlib.util.find_spec("numba") is not None
    except (ImportError, ValueError):  # a broken install, or numba blocked (sys.modules["numba"] = None)
        return False


def use_numba() -> bool:
    """True when the compiled kernels should run (module docstring)."""
    choice = os.environ.get(ENV, "numba").strip().lower() or "numba"
    if choice not in CHOICES:
        raise VoxposeError(f"{ENV}={choice!r}: expected one of {', '.join(CHOICES)}")
    return choice == "numba" and numba_available()


def jit(fn):
    """Mark ``fn`` a kernel: at the first call of any kernel of its module, numba is imported and every kernel of
    the module is replaced by ``numba.njit(cache=True, nogil=True)`` of itself, so that kernels calling each
    other are compiled together (call kernels as ``module.name``, never by a name imported earlier)."""
    _pending.setdefault(fn.__module__, []).append(fn)

    @functools.wraps(fn)
    def first_call(*args):
        return getattr(_compile(fn.__module__), fn.__name__)(*args)

    return first_call


def _compile(module_name: str):
    """The module, its kernels replaced by numba dispatchers (compiled, or loaded from the cache, when called)."""
    module = sys.modules[module_name]
    with _lock:
        kernels = _pending.pop(module_name, [])
        if kernels:
            import numba

            for fn in kernels:
                setattr(module, fn.__name__, numba.njit(cache=True, nogil=True)(fn))
    return module


def load_runtime() -> None:
    """Import numba, turn every kernel imported so far into a dispatcher and set up numba's CPU target (what the
    first cached call would do: 0.4 - 0.5 s): for a process whose forks run kernels (``voxpose.cli.job_server``).
    """
    for name in list(_pending):
        _compile(name)
    from numba.core.registry import cpu_target

    cpu_target.target_context.refresh()
