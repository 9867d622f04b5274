"""Print the SIMD features that numpy dispatches to on this machine, above its baseline.

``make test`` runs the notebooks a second time with these disabled
(``NPY_DISABLE_CPU_FEATURES``), so that numpy takes other floating-point paths than in the
first run: the X86_V2 baseline instead of AVX2 and AVX-512 on x86-64, plain NEON on arm64.
A particle filter's single run differs between the two (the chapters' claims about random runs
must hold on both); a deterministic cell's stored output must not.

``--check`` instead verifies that the features named in ``NPY_DISABLE_CPU_FEATURES`` are off
in this process, and prints what numpy uses.
"""

import os
import sys

from numpy._core._multiarray_umath import (  # the tables numpy.show_runtime() prints
    __cpu_baseline__,
    __cpu_dispatch__,
    __cpu_features__,
)


def found() -> list[str]:
    """The dispatch targets of this numpy build that this CPU has."""
    return [name for name in __cpu_dispatch__ if __cpu_features__.get(name)]


def main(argv: list[str]) -> int:
    if argv[1:] == ["--check"]:
        disabled = os.environ.get("NPY_DISABLE_CPU_FEATURES", "").replace(",", " ").split()
        still_on = [name for name in disabled if __cpu_features__.get(name)]
        print(
            f"numpy: baseline {' '.join(__cpu_baseline__)}; dispatched to "
            f"{' '.join(found()) or 'nothing above the baseline'}; "
            f"disabled: {' '.join(disabled) or 'none'}"
        )
        if still_on:
            print(f"NPY_DISABLE_CPU_FEATURES did not disable {still_on}", file=sys.stderr)
            return 1
        return 0
    if len(argv) > 1:
        print(f"usage: {argv[0]} [--check]", file=sys.stderr)
        return 2
    print(" ".join(found()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
