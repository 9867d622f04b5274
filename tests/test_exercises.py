"""The exercise checks, and the exercise pattern of every chapter notebook."""

from pathlib import Path

import nbformat
import numpy as np
import pytest

from probrob.exercises import check, verdict

NOTEBOOKS = sorted((Path(__file__).parent.parent / "notebooks").glob("*.ipynb"))


def test_missing_answer_is_reported_not_raised(capsys):
    assert check("Ex 1", None, 3.0) is None
    check("Ex 1", ..., 3.0)
    assert capsys.readouterr().out.count("Ex 1: not yet — no answer yet") == 2


@pytest.mark.parametrize(
    ("answer", "message"),
    [
        (3.0, "correct"),
        (3.0 + 1e-9, "correct"),
        (3.5, "not yet — too large"),
        (2.0, "not yet — too small"),
        ([3.0, 3.0], "expected shape ()"),
        ("three", "expected a number"),
        (float("nan"), "NaN"),
    ],
)
def test_expected_values(capsys, answer, message):
    check("Ex", answer, 3.0)
    out = capsys.readouterr().out
    assert message in out and out.startswith("Ex: ")
    assert out.strip() == verdict("Ex", answer, 3.0)
    assert "3.0" not in out.replace(str(answer), "")  # the expected value is never shown


def test_property_tests_never_raise(capsys):
    check("Ex", 2, test=lambda a: None if a % 2 == 0 else "odd")
    check("Ex", 3, test=lambda a: None if a % 2 == 0 else "odd")
    check("Ex", 3, test=lambda a: a % 2 == 0)
    check("Ex", "x", test=lambda a: np.sqrt(a))
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "Ex: correct"
    assert out[1] == "Ex: not yet — odd"
    assert out[2] == "Ex: not yet — the answer does not pass the check"
    assert out[3].startswith("Ex: not yet — checking the answer raised")


def _outputs(cell):
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_exercise_starts_unsolved_and_has_a_collapsed_solution(path):
    """Each solution cell (tag ``exercise-solution``) is collapsed (``hide-cell`` or
    ``hide-input``) and prints
    "<Exercise>: correct" (nbval re-runs it and compares); an earlier cell, the check of the
    reader's answer as shipped, prints "<Exercise>: not yet" (the book shows it unsolved)."""
    cells = [c for c in nbformat.read(path, as_version=4).cells if c.cell_type == "code"]
    for k, cell in enumerate(cells):
        if "exercise-solution" not in cell.metadata.get("tags", []):
            continue
        assert {"hide-cell", "hide-input"} & set(cell.metadata["tags"]), cell.source
        out = _outputs(cell)
        solved = [line.split(": correct")[0] for line in out.splitlines() if ": correct" in line]
        assert solved and "not yet" not in out, cell.source
        unsolved = [_outputs(c) for c in cells[:k]]
        for name in solved:
            assert any(f"{name}: not yet" in text for text in unsolved), (name, path.name)
    for cell in cells:
        if "exercise-check" in cell.metadata.get("tags", []):
            assert "not yet" in _outputs(cell), cell.source


def test_the_motion_chapter_has_at_least_five_exercises():
    path = next(p for p in NOTEBOOKS if p.stem == "trabalho3_motion_models")
    cells = nbformat.read(path, as_version=4).cells
    solutions = [c for c in cells if "exercise-solution" in c.metadata.get("tags", [])]
    assert len(solutions) >= 5
    # at least two solutions are code that calls the library's models
    models = ("motion_model_", "sample_motion_model_", "velocity_motion(")
    assert sum(any(m in c.source for m in models) for c in solutions) >= 2
