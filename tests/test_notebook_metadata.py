"""Every stored notebook is what JupyterLab writes, without run-to-run metadata.

JupyterLab writes the kernelspec of the venv's ipykernel into a notebook as soon as its kernel
connects; a notebook stored with another one is marked modified on opening, and autosave then
changes the checkout. The widget state and the execution timestamps change on every run.
``.ci/normalize_notebooks.py`` (the Makefile's STRIP_VOLATILE step) stores notebooks this way.
"""

from __future__ import annotations

import copy
import importlib.util
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb")) + sorted(
    (ROOT / ".ci" / "fixtures").glob("*.ipynb")
)


def _normalize_module():
    spec = importlib.util.spec_from_file_location(
        "probrob_ci_normalize", ROOT / ".ci" / "normalize_notebooks.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


NORMALIZE = _normalize_module()


def test_there_are_notebooks():
    assert len([p for p in NOTEBOOKS if p.parent.name == "notebooks"]) >= 6


def test_kernelspec_is_the_one_jupyterlab_writes():
    # ipykernel's own kernelspec (what `python -m ipykernel install` writes into the venv and
    # JupyterLab copies into the notebook), not a constant typed here
    from ipykernel.kernelspec import get_kernel_dict

    spec = get_kernel_dict()
    assert NORMALIZE.kernelspec() == {
        "display_name": spec["display_name"],
        "language": "python",
        "name": "python3",
    }
    assert spec["display_name"] == "Python 3 (ipykernel)"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_is_stored_normalised(path):
    nb = nbformat.read(path, as_version=4)
    assert nb.metadata.get("kernelspec") == NORMALIZE.kernelspec(), (
        f"{path.name}: kernelspec {nb.metadata.get('kernelspec')} is not what JupyterLab "
        "writes: run `python .ci/normalize_notebooks.py` on it"
    )
    assert "widgets" not in nb.metadata, f"{path.name}: widget state stored"
    for i, cell in enumerate(nb.cells):
        assert "execution" not in cell.metadata, f"{path.name}: cell {i} has execution times"
        assert "user_expressions" not in cell.metadata, (
            f"{path.name}: cell {i} stores {{eval}} values from a JupyterLab run"
        )
    # and the normalisation has nothing left to change
    assert not NORMALIZE.normalize(copy.deepcopy(nb)), f"{path.name} is not normalised"


def test_random_output_ids_become_stable():
    # two runs of the same notebook differ only in their random ids; normalised, they are equal
    import uuid

    def run():
        nb = nbformat.v4.new_notebook()
        a, b = uuid.uuid4().hex, uuid.uuid4().hex
        html = f'<img id="_anim_img{a}"><script>anim{a} = new Animation("_anim_img{a}")</script>'
        nb.cells = [
            nbformat.v4.new_code_cell(
                "w", id="w", outputs=[nbformat.v4.new_output("display_data", {"text/html": html})]
            ),
            nbformat.v4.new_code_cell(
                "v",
                id="v",
                outputs=[
                    nbformat.v4.new_output(
                        "display_data",
                        {"application/vnd.jupyter.widget-view+json": {"model_id": b}},
                    )
                ],
            ),
        ]
        NORMALIZE.normalize(nb)
        return nb

    first, second = run(), run()
    assert nbformat.writes(first) == nbformat.writes(second)
    html = first.cells[0].outputs[0].data["text/html"]
    ids = set(NORMALIZE.HEX_ID.findall(html))
    assert len(ids) == 1  # one id, used consistently in the player
    model = first.cells[1].outputs[0].data["application/vnd.jupyter.widget-view+json"]["model_id"]
    assert model not in ids  # and distinct ids stay distinct
    # a 64-hex digest (e.g. a sha256 printed by a cell) is not an id
    digest = "ab" * 32
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_code_cell("d", outputs=[nbformat.v4.new_output("stream", text=digest)])
    ]
    NORMALIZE.normalize(nb)
    assert nb.cells[0].outputs[0].text == digest


def test_normalize_fixes_what_jupyterlab_would_change():
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {
        "display_name": "Python 3",
        "language": "python",
        "name": "python3",
    }
    nb.metadata["widgets"] = {"application/vnd.jupyter.widget-state+json": {"state": {}}}
    nb.cells = [
        nbformat.v4.new_code_cell("1", metadata={"execution": {"iopub.status.busy": "t"}}),
        nbformat.v4.new_markdown_cell("{eval}`x`", metadata={"user_expressions": [{}]}),
    ]
    assert NORMALIZE.normalize(nb)
    assert nb.metadata["kernelspec"]["display_name"] == "Python 3 (ipykernel)"
    assert "widgets" not in nb.metadata
    assert nb.cells[0].metadata == {} and nb.cells[1].metadata == {}
    assert not NORMALIZE.normalize(nb)  # idempotent
