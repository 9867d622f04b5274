#!/usr/bin/env python3
"""Store notebooks as JupyterLab writes them, without the metadata that changes on every run.

Usage:  python .ci/normalize_notebooks.py NOTEBOOK.ipynb ...   (the Makefile's STRIP_VOLATILE)

For each notebook, in place:
  * ``metadata.kernelspec`` becomes the kernelspec that ipykernel installs in the venv
    (``{"display_name": "Python 3 (ipykernel)", "language": "python", "name": "python3"}``).
    JupyterLab writes that one into the notebook as soon as the kernel connects, so a notebook
    stored with another (e.g. "Python 3") is marked modified on opening, and autosave then
    changes the checkout;
  * ``metadata.widgets`` (the ipywidgets state: fresh model ids on every run; the live sliders
    are re-created by *Run All*) is dropped;
  * each cell's ``metadata.execution`` (execution timestamps) is dropped;
  * the random 32-hex ids in code cells' outputs (ipywidgets model ids, the ids with which
    ``to_jshtml`` names a player's elements: ``uuid4().hex``) are replaced by ids derived from
    their order in the notebook, the same id by the same one everywhere, so that re-executing
    an unchanged notebook leaves its file unchanged (nbval masks these ids in any case);
  * each markdown cell's ``metadata.user_expressions`` (the ``{eval}`` values jupyterlab-myst
    stores after a run in JupyterLab; they would go stale when the code changes, and the book
    evaluates the roles itself) is dropped.
A notebook that is already normalised is not rewritten. ``normalize(nb)`` is the same step on an
``nbformat`` notebook (``tests/test_notebook_metadata.py`` checks that it changes nothing).
"""

from __future__ import annotations

import hashlib
import json
import re
import sys

import nbformat
from ipykernel.kernelspec import KERNEL_NAME, get_kernel_dict


def kernelspec() -> dict:
    """The kernelspec JupyterLab writes for the venv's ipykernel: display_name, language, name."""
    spec = get_kernel_dict()
    return {
        "display_name": spec["display_name"],
        "language": spec["language"],
        "name": KERNEL_NAME,
    }


# 32 hex digits not inside a longer hex run: a widget model id ("model_id": "<hex>") or a
# to_jshtml id glued to its prefix (_anim_img<hex>, anim<hex>). (A 32-long pure-hex run inside
# base64 image data would have odds of about 4**-32 per position.)
HEX_ID = re.compile(r"(?<![0-9a-f])[0-9a-f]{32}(?![0-9a-f])")


def _stable_ids(nb) -> None:
    """Replace every 32-hex id in the outputs by one numbered in order of first appearance."""
    ids: dict[str, str] = {}

    def stable(m: re.Match) -> str:
        if m.group(0) not in ids:
            ids[m.group(0)] = hashlib.sha256(f"probrob-id-{len(ids)}".encode()).hexdigest()[:32]
        return ids[m.group(0)]

    for cell in nb.cells:
        if cell.cell_type == "code" and cell.outputs:
            text = json.dumps(cell.outputs)
            if HEX_ID.search(text):
                cell.outputs = nbformat.from_dict(json.loads(HEX_ID.sub(stable, text)))


def normalize(nb) -> bool:
    """Normalise ``nb`` (an nbformat NotebookNode) in place; return True if it changed."""
    before = nbformat.writes(nb)
    nb.metadata["kernelspec"] = kernelspec()
    nb.metadata.pop("widgets", None)
    _stable_ids(nb)
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
        if cell.cell_type == "markdown":
            cell.metadata.pop("user_expressions", None)
    return nbformat.writes(nb) != before


def main(paths: list[str]) -> int:
    for path in paths:
        nb = nbformat.read(path, as_version=4)
        if normalize(nb):
            nbformat.write(nb, path)
            print(f"normalised {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
