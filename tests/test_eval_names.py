"""Every ``{eval}`` role of a chapter names a variable that one of its code cells assigns.

The book (and jupyterlab-myst) evaluates each role in the kernel after Run All; a name that no
cell defines is a NameError in the build (a warning under -W) and an empty number in JupyterLab.
This finds it without running the chapter. (Expressions that are not plain names are evaluated
for their names.)
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
ROLE = re.compile(r"\{eval\}`([^`]+)`")


def _assigned(source: str) -> set[str]:
    tree = ast.parse(source)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.FunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
        elif isinstance(node, ast.Global):
            names.update(node.names)
    return names


def _code_names(nb) -> set[str]:
    names = set()
    for cell in nb.cells:
        if cell.cell_type == "code" and "exercise-solution" not in cell.metadata.get("tags", []):
            names |= _assigned(cell.source)
        if cell.cell_type == "code" and "globals()[" in cell.source:
            # names made by globals()[f"{prefix}_..."] = ...: the prefixes the chapter passes
            names.add("*globals*")
    return names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_eval_role_names_a_variable_of_the_chapter(path):
    nb = nbformat.read(path, as_version=4)
    defined = _code_names(nb)
    missing = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "markdown":
            continue
        for expr in ROLE.findall(cell.source):
            used = {
                n.id for n in ast.walk(ast.parse(expr, mode="eval")) if isinstance(n, ast.Name)
            }
            missing += [f"cell {i}: {name}" for name in used - defined]
    if "*globals*" in defined:  # MRCLAM names its tables' cells through globals()[f"..."]
        pytest.skip(f"{path.name} makes names through globals(); the book's build checks them")
    assert not missing, f"{path.name}: {{eval}} names no code cell assigns: {missing}"


def _early_roles(nb) -> list[str]:
    """The roles of markdown cells above the first code cell that assigns their names."""
    defined, early = set(), []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code" and "exercise-solution" not in cell.metadata.get("tags", []):
            defined |= _assigned(cell.source)
        elif cell.cell_type == "markdown":
            for expr in ROLE.findall(cell.source):
                tree = ast.parse(expr, mode="eval")
                used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
                early += [f"cell {i}: {name}" for name in sorted(used - defined)]
    return early


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_eval_role_comes_after_the_cell_that_assigns_its_name(path):
    # The book evaluates a role when its cell is rendered, in the kernel as Run All leaves it
    # at that point: a role above the cell that assigns its name is a NameError in the build
    # (the grid localization section had three, which only `make book` found).
    nb = nbformat.read(path, as_version=4)
    if "*globals*" in _code_names(nb):
        pytest.skip(f"{path.name} makes names through globals(); the book's build checks them")
    early = _early_roles(nb)
    assert not early, f"{path.name}: {{eval}} roles above the cell that assigns them: {early}"


def test_the_order_check_can_fail():
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("{eval}`late` before it is set, {eval}`early` after"),
        nbformat.v4.new_code_cell("late = 1"),
        nbformat.v4.new_markdown_cell("{eval}`late`"),
    ]
    nb.cells.insert(0, nbformat.v4.new_code_cell("early = 0"))
    assert _early_roles(nb) == ["cell 1: late"]
