"""The exercise checks, and the exercise pattern of every chapter notebook.

Every chapter has at least four exercises; every check cell calls a function of the
chapter's checks module ``probrob.exercises.<module>`` (:data:`CHAPTER_MODULES`); every such
function has wrong-answer tests in ``tests/test_exercises_<module>.py``, read from that file's
``WRONG_ANSWERS`` registry (``{"exercise_1": [wrong, ...], ...}``, at least three each) or,
for a file without one, found by name in its source.
"""

import ast
import importlib
import importlib.util
import inspect
from pathlib import Path

import nbformat
import numpy as np
import pytest

from probrob.exercises import check, verdict

TESTS = Path(__file__).parent
NOTEBOOKS = sorted((TESTS.parent / "notebooks").glob("*.ipynb"))
CHAPTER_MODULES = {
    "trabalho3_motion_models": "trabalho3",
    "turkish_lecture_motion": "turkish",
    "cir_odometry": "cir",
    "mrclam_motion_noise": "mrclam",
    "trabalho4_measurement_models": "trabalho4",
    "trabalho5_localization": "trabalho5",
    "mcl_intel_lab": "mcl",
}


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


def _tagged(path, tag):
    cells = nbformat.read(path, as_version=4).cells
    return [c for c in cells if c.cell_type == "code" and tag in c.metadata.get("tags", [])]


def _checks_module(path):
    """The chapter's ``probrob.exercises.<module>``, or a clear failure if it is missing."""
    assert path.stem in CHAPTER_MODULES, f"{path.name}: add its checks module to CHAPTER_MODULES"
    name = f"probrob.exercises.{CHAPTER_MODULES[path.stem]}"
    if importlib.util.find_spec(name) is None:
        pytest.fail(f"{path.name}: its checks module {name} does not exist yet")
    return importlib.import_module(name)


def _aliases(path, module):
    """Names under which the notebook imports ``module`` (``from probrob.exercises import
    cir as ch``, ``import probrob.exercises.cir as ch``)."""
    short = module.__name__.rsplit(".", 1)[1]
    names = set()
    for cell in nbformat.read(path, as_version=4).cells:
        if cell.cell_type != "code":
            continue
        try:
            tree = ast.parse(cell.source)
        except SyntaxError:  # IPython magics: no import of a checks module there
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module == "probrob.exercises":
                names |= {a.asname or a.name for a in node.names if a.name == short}
            elif isinstance(node, ast.Import):
                names |= {a.asname for a in node.names if a.name == module.__name__ and a.asname}
    return names


def _check_functions(path):
    """The module functions the check cells pass as ``test=``: {name, ...}."""
    module = _checks_module(path)
    aliases = _aliases(path, module)
    assert aliases, f"{path.name} does not import {module.__name__}"
    used = set()
    for cell in _tagged(path, "exercise-check"):
        calls = [
            node
            for node in ast.walk(ast.parse(cell.source))
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "check"
        ]
        assert calls, f"{path.name}: a check cell that calls no check(): {cell.source!r}"
        for call in calls:
            test = next((k.value for k in call.keywords if k.arg == "test"), None)
            ok = (
                isinstance(test, ast.Attribute)
                and isinstance(test.value, ast.Name)
                and test.value.id in aliases
            )
            assert ok, (
                f"{path.name}: check(..., test=...) must name a function of {module.__name__}: {cell.source!r}"
            )
            assert inspect.isfunction(getattr(module, test.attr, None)), (path.name, test.attr)
            used.add(test.attr)
    return module, used


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_chapter_has_at_least_four_exercises(path):
    checks, solutions = _tagged(path, "exercise-check"), _tagged(path, "exercise-solution")
    assert len(checks) >= 4, f"{path.name}: {len(checks)} check cells, at least 4 needed"
    assert len(solutions) >= 4, f"{path.name}: {len(solutions)} solutions, at least 4 needed"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_check_cell_calls_the_chapters_checks_module(path):
    _, used = _check_functions(path)
    assert len(used) >= 4, (path.name, used)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_check_function_has_wrong_answer_tests(path):
    module, used = _check_functions(path)
    short = module.__name__.rsplit(".", 1)[1]
    test_file = TESTS / f"test_exercises_{short}.py"
    assert test_file.exists(), f"{path.name}: no wrong-answer tests, {test_file.name} is missing"
    spec = importlib.util.spec_from_file_location(f"_wrong_answers_{short}", test_file)
    tests = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tests)
    functions = used | {
        n for n, f in vars(module).items() if n.startswith("exercise_") and inspect.isfunction(f)
    }
    registry = getattr(tests, "WRONG_ANSWERS", None)
    for name in sorted(functions):
        if registry is not None:
            wrong = registry.get(name, [])
            assert len(wrong) >= 3, (
                f"{test_file.name}: {name} has {len(wrong)} wrong answers, not 3"
            )
        else:
            assert name in test_file.read_text(encoding="utf-8"), (
                f"{test_file.name} never tests {name}"
            )
