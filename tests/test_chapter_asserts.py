"""A chapter's asserts guard its sentences: change one constant, and the sentence's assert fails.

The CIR chapter (the fastest to run) says in its cell after the first step's figure that the
step "turns right (clockwise)" about a CIR "beyond the right wheel". The cell that computes
the step asserts it. Swapping the two wheel arcs of that step makes it a left turn: the
notebook, executed as the book build and nbval execute it, must stop in that cell with the
assert's message, and run through unchanged otherwise.
"""

import sys
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

NOTEBOOK = Path(__file__).parent.parent / "notebooks" / "cir_odometry.ipynb"
CONSTANT = "u = np.array([0.6, 0.3])  # s_sx, s_dx [m]"
CHANGED = "u = np.array([0.3, 0.6])  # s_sx, s_dx [m]"
MESSAGE = "cell 9: a right turn, the CIR beyond the right wheel"


@pytest.fixture
def this_venvs_kernel(monkeypatch):
    # the "python3" kernel must be this interpreter (as the Makefile's JUPYTER_PATH ensures)
    monkeypatch.setenv("JUPYTER_PATH", str(Path(sys.prefix) / "share" / "jupyter"))
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")


def _run(nb):
    client = NotebookClient(
        nb,
        timeout=60,
        kernel_name="python3",
        resources={"metadata": {"path": str(NOTEBOOK.parent)}},
    )
    client.execute()


def _changed_notebook():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    where = [k for k, c in enumerate(nb.cells) if c.cell_type == "code" and CONSTANT in c.source]
    assert len(where) == 1, "the constant this test changes is no longer in the chapter"
    k = where[0]
    for cell in nb.cells:  # as the book build starts: nothing executed
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    assert f'"{MESSAGE}"' in nb.cells[k].source, "the assert is no longer in that cell"
    return nb, k


def test_changing_one_constant_fails_the_assert_of_its_sentence(this_venvs_kernel):
    nb, k = _changed_notebook()
    nb.cells[k].source = nb.cells[k].source.replace(CONSTANT, CHANGED)
    with pytest.raises(CellExecutionError) as failure:
        _run(nb)
    assert failure.value.ename == "AssertionError"
    assert MESSAGE in failure.value.evalue
    # the failure is in the changed cell: it holds the error output; no later cell ran
    errors = [
        j
        for j, cell in enumerate(nb.cells)
        if cell.cell_type == "code" and any(o.output_type == "error" for o in cell.outputs)
    ]
    assert errors == [k]
    assert all(
        cell.execution_count is None and not cell.outputs
        for cell in nb.cells[k + 1 :]
        if cell.cell_type == "code"
    )


def test_the_unchanged_cells_up_to_it_pass(this_venvs_kernel):
    nb, k = _changed_notebook()
    nb.cells = nb.cells[: k + 1]  # the same cells, the constant as shipped
    _run(nb)
    assert not any(
        o.output_type == "error" for c in nb.cells if c.cell_type == "code" for o in c.outputs
    )
    assert nb.cells[k].execution_count is not None
