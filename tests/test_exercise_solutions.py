"""Every exercise's solution, run: each chapter executed afresh with each solution's code inserted
as a cell right after its check cell, as a reader pasting it would, and each must print
"<Exercise>: correct".

The stored chapters keep their solutions in collapsed markdown boxes, out of the way of
JupyterLab's Run All (``tests/test_exercises.py`` checks that form), so nbval never runs them;
this test is what proves that each exercise can be solved and that its solution is right.
It executes every chapter once more (about as long as nbval). ``make test`` runs it twice: with
numpy's default floating-point path and, in ``make nbval-fp``, with the SIMD features above the
baseline disabled (``NPY_DISABLE_CPU_FEATURES``); the kernel is then checked to run without them.
"""

import os
import sys
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "_ext")]
import probrob_zmq_wakeup  # noqa: E402  (a kernel reply is read within 1 s, not at the timeout)
from jupyter_client.channels import AsyncZMQSocketChannel  # noqa: E402
from test_exercises import NOTEBOOKS, check_names, solutions  # noqa: E402

CELL_TIMEOUT = 120  # s, the Makefile's CELL_TIMEOUT (tests/test_tooling.py keeps them equal)


def _with_solutions(path):
    """The chapter with each solution's code as a code cell after its check cell, and the
    indices of those cells: ``(notebook, {index: exercise name})``."""
    nb = nbformat.read(path, as_version=4)
    code = dict(solutions(path))
    cells, inserted = [], {}
    for cell in nb.cells:
        if "exercise-solution" in cell.metadata.get("tags", []):
            continue
        cells.append(cell)
        if "exercise-check" in cell.metadata.get("tags", []):
            name = next(n for n in check_names(cell.source) if n in code)
            inserted[len(cells)] = name
            cells.append(nbformat.v4.new_code_cell(code.pop(name)))
    assert not code, f"{path.name}: solutions without a check cell: {sorted(code)}"
    nb.cells = cells
    return nb, inserted


_FEATURES_OFF = """\
from numpy._core._multiarray_umath import __cpu_features__
assert not any(__cpu_features__.get(f) for f in {!r}), "NPY_DISABLE_CPU_FEATURES not applied"
"""


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_solution_prints_correct(path, monkeypatch):
    # the build's stall fix, for this test only (tests/test_zmq_wakeup.py tests it unpatched)
    monkeypatch.setattr(AsyncZMQSocketChannel, "get_msg", AsyncZMQSocketChannel.get_msg)
    probrob_zmq_wakeup.install()
    nb, inserted = _with_solutions(path)
    assert len(inserted) >= 4, path.name
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}  # the kernel's own backend
    client = NotebookClient(
        nb,
        timeout=CELL_TIMEOUT,
        startup_timeout=60,
        kernel_name=nb.metadata.get("kernelspec", {}).get("name", "python3"),
        resources={"metadata": {"path": str(path.parent)}},
    )
    disabled = os.environ.get("NPY_DISABLE_CPU_FEATURES", "").replace(",", " ").split()
    if disabled:  # the kernel takes the other floating-point path (make nbval-fp)
        nb.cells.insert(0, nbformat.v4.new_code_cell(_FEATURES_OFF.format(disabled)))
        inserted = {k + 1: name for k, name in inserted.items()}
    client.execute(env=env)  # a cell that raises fails the test, naming the cell
    wrong = []
    for k, name in inserted.items():
        out = "".join(o.get("text", "") for o in nb.cells[k].outputs if o.output_type == "stream")
        if f"{name}: correct" not in out or "not yet" in out:
            wrong.append(f"{name}: {out.strip()[-300:]!r}")
    assert not wrong, f"{path.name}: solutions that are not correct: {wrong}"
