"""Print the SIMD features that numpy dispatches to on this machine, above its baseline.

``make test`` runs the notebooks a second time with these disabled
(``NPY_DISABLE_CPU_FEATURES``), so that numpy takes other floating-point paths than in the
first run: the X86_V2 baseline instead of AVX2 and AVX-512 on x86-64, plain NEON on arm64.
A particle filter's single run differs between the two (the chapters' claims about random runs
must hold on both); a deterministic cell's stored output must not.

The matrix products go through OpenBLAS, which picks its kernels per CPU model on its own
(AVX-512 ones on one machine, Haswell's on another), so a sum that is 0 in exact arithmetic
may come out +1e-17 here and -1e-17 there. ``--blas`` prints the ``OPENBLAS_CORETYPE`` that the
second run forces, the oldest kernels of this architecture (Prescott's SSE3 ones on x86-64,
plain ARMv8 on arm64), so that it differs from the first run in those too.

``--check`` instead verifies that the features named in ``NPY_DISABLE_CPU_FEATURES`` are off
in this process, and prints what numpy uses and which OpenBLAS kernels it runs.
"""

import ctypes
import os
import platform
import sys
from pathlib import Path

import numpy
from numpy._core._multiarray_umath import (  # the tables numpy.show_runtime() prints
    __cpu_baseline__,
    __cpu_dispatch__,
    __cpu_features__,
)

# OPENBLAS_CORETYPE of the oldest kernels that every CPU of the architecture runs
OLDEST_BLAS_KERNELS = {"x86_64": "Prescott", "AMD64": "Prescott", "aarch64": "ARMV8"}


def found() -> list[str]:
    """The dispatch targets of this numpy build that this CPU has."""
    return [name for name in __cpu_dispatch__ if __cpu_features__.get(name)]


def blas_kernels() -> str:
    """The name of the kernels that numpy's bundled OpenBLAS runs here, or why it is unknown."""
    libs = sorted(Path(numpy.__file__).parent.parent.glob("numpy.libs/libscipy_openblas*"))
    if not libs:
        return "unknown (no bundled OpenBLAS)"
    lib = ctypes.CDLL(str(libs[0]))
    for name in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename"):
        if hasattr(lib, name):
            corename = getattr(lib, name)
            corename.restype = ctypes.c_char_p
            return corename().decode()
    return f"unknown ({libs[0].name} does not say)"


def main(argv: list[str]) -> int:
    if argv[1:] == ["--check"]:
        disabled = os.environ.get("NPY_DISABLE_CPU_FEATURES", "").replace(",", " ").split()
        still_on = [name for name in disabled if __cpu_features__.get(name)]
        print(
            f"numpy: baseline {' '.join(__cpu_baseline__)}; dispatched to "
            f"{' '.join(found()) or 'nothing above the baseline'}; "
            f"disabled: {' '.join(disabled) or 'none'}; "
            f"OpenBLAS kernels: {blas_kernels()} "
            f"(OPENBLAS_CORETYPE={os.environ.get('OPENBLAS_CORETYPE', '')!r})"
        )
        if still_on:
            print(f"NPY_DISABLE_CPU_FEATURES did not disable {still_on}", file=sys.stderr)
            return 1
        return 0
    if argv[1:] == ["--blas"]:
        print(OLDEST_BLAS_KERNELS.get(platform.machine(), ""))
        return 0
    if len(argv) > 1:
        print(f"usage: {argv[0]} [--check | --blas]", file=sys.stderr)
        return 2
    print(" ".join(found()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
