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
import re
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


def _tags(cell):
    return set(cell.metadata.get("tags", []))


# A solution is a markdown cell, so that JupyterLab's Run All never runs it: a collapsed
# "Solution to Exercise N" box holding one Python block (and, after it, any explanation).
SOLUTION = re.compile(
    r"\A:::\{dropdown\} Solution to (?P<name>Exercise \d+)\n"
    r"```python\n(?P<code>.*?)\n```\n(?P<prose>.*?):::\s*\Z",
    re.S,
)


def check_names(source):
    """The exercise names of the ``check("Exercise N", ...)`` calls in ``source``."""
    return [
        node.args[0].value
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.Call)
        and getattr(node.func, "id", None) == "check"
        and node.args
        and isinstance(node.args[0], ast.Constant)
    ]


def solutions(path):
    """``[(exercise name, solution code), ...]`` of a notebook, in order, each right after its
    check cell; fails if a solution is not of the form :data:`SOLUTION` describes."""
    cells = nbformat.read(path, as_version=4).cells
    found = []
    for k, cell in enumerate(cells):
        if "exercise-solution" not in _tags(cell):
            continue
        assert cell.cell_type == "markdown", (
            f"{path.name}: cell {k} is a solution in a {cell.cell_type} cell: Run All would run "
            "it; make it a markdown ':::{dropdown} Solution to Exercise N' box"
        )
        m = SOLUTION.match(cell.source)
        assert m, f"{path.name}: cell {k} is not a 'Solution to Exercise N' box: {cell.source!r}"
        assert "```" not in m["prose"], f"{path.name}: cell {k} holds more than one code block"
        before = cells[k - 1]
        assert "exercise-check" in _tags(before), (
            f"{path.name}: the solution in cell {k} does not follow its check cell"
        )
        assert m["name"] in check_names(before.source), (path.name, k, m["name"])
        assert m["name"] in check_names(m["code"]), (
            f"{path.name}: the solution to {m['name']} does not end with its check"
        )
        found.append((m["name"], m["code"]))
    return found


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_exercise_starts_unsolved_and_has_a_solution_out_of_run_all(path):
    """Each check cell prints "<Exercise>: not yet" as shipped (the stored output, which nbval
    reproduces), and is followed by its solution, a collapsed markdown box that Run All does not
    run (tests/test_exercise_solutions.py runs each solution and requires "correct")."""
    cells = nbformat.read(path, as_version=4).cells
    checks = [c for c in cells if "exercise-check" in _tags(c)]
    for cell in checks:
        assert cell.cell_type == "code" and "not yet" in _outputs(cell), cell.source
    names = [name for name, _ in solutions(path)]
    assert len(names) == len(checks) == len(set(names)), (path.name, names, len(checks))


def _placeholder(node):
    """A value that gives nothing away: None, ``...``, or a tuple/list of them."""
    if isinstance(node, ast.Constant):
        return node.value is None or node.value is Ellipsis
    if isinstance(node, ast.Tuple | ast.List):
        return all(_placeholder(e) for e in node.elts)
    return False


def _given(node):
    """Data a check may be given (``partial(ch.exercise_2, pose=x0, fit=fits["a", 1].alpha)``):
    names, constants, their items and attributes; never a call or arithmetic, which could
    compute the answer."""
    if isinstance(node, ast.Name | ast.Constant):
        return True
    if isinstance(node, ast.Tuple):
        return all(_given(e) for e in node.elts)
    if isinstance(node, ast.Attribute):
        return _given(node.value)
    if isinstance(node, ast.Subscript):
        return _given(node.value) and _given(node.slice)
    return False


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_check_cells_hold_no_answer(path):
    """A check cell is ``check("Exercise N", answer, test=ch.exercise_N)`` (or a ``partial`` of
    given data) and nothing else; the latest cell before it that sets ``answer`` sets it to a
    placeholder (``None``), so the notebook as shipped does not hold the answer."""
    cells = nbformat.read(path, as_version=4).cells
    for k, cell in enumerate(cells):
        if "exercise-check" not in _tags(cell):
            continue
        body = ast.parse(cell.source).body
        assert len(body) == 1 and isinstance(body[0], ast.Expr), (path.name, cell.source)
        call = body[0].value
        assert isinstance(call, ast.Call) and getattr(call.func, "id", None) == "check", (
            path.name,
            cell.source,
        )
        assert len(call.args) == 2 and isinstance(call.args[0], ast.Constant), cell.source
        assert isinstance(call.args[1], ast.Name), (
            f"{path.name}: the check's answer must be the reader's variable: {cell.source!r}"
        )
        assert [kw.arg for kw in call.keywords] == ["test"], cell.source
        test = call.keywords[0].value
        if isinstance(test, ast.Call):
            assert getattr(test.func, "id", None) == "partial", cell.source
            given = test.args[1:] + [kw.value for kw in test.keywords]
            assert all(_given(g) for g in given), (
                f"{path.name}: a check computes something from given data: {cell.source!r}"
            )
        name = call.args[1].id
        setters = []
        for c in cells[:k]:
            if c.cell_type != "code" or "exercise-solution" in _tags(c):
                continue
            try:
                tree = ast.parse(c.source)
            except SyntaxError:
                continue
            for node in ast.walk(tree):
                if isinstance(node, ast.Assign) and any(
                    isinstance(t, ast.Name) and t.id == name for t in node.targets
                ):
                    setters.append(node.value)
                elif isinstance(node, ast.FunctionDef) and node.name == name:
                    setters.append(node)  # the reader writes a function (its stub fails)
        assert setters, f"{path.name}: {name} is never set before its check"
        if isinstance(setters[-1], ast.FunctionDef):
            continue  # a stub: the stored "not yet" of the check shows it is not the answer
        assert _placeholder(setters[-1]), (
            f"{path.name}: {name} is set to {ast.unparse(setters[-1])!r} before its check, "
            "not to a placeholder (None): the notebook would hold the answer"
        )


def test_the_motion_chapter_has_at_least_five_exercises():
    path = next(p for p in NOTEBOOKS if p.stem == "trabalho3_motion_models")
    codes = [code for _, code in solutions(path)]
    assert len(codes) >= 5
    # at least two solutions are code that calls the library's models
    models = ("motion_model_", "sample_motion_model_", "velocity_motion(")
    assert sum(any(m in code for m in models) for code in codes) >= 2


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
            if (
                isinstance(test, ast.Call)
                and getattr(test.func, "id", None) == "partial"
                and test.args
            ):
                test = test.args[0]  # functools.partial(ch.exercise_1, data=...): the function
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
    checks, solved = _tagged(path, "exercise-check"), solutions(path)
    assert len(checks) >= 4, f"{path.name}: {len(checks)} check cells, at least 4 needed"
    assert len(solved) >= 4, f"{path.name}: {len(solved)} solutions, at least 4 needed"


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


# --------------------------------------------------------------------------- issue 23, item 4
# A string, a bool or NaN is never a right answer, in any chapter: numpy reads "625" as 625.0
# and False as 0.0, and NaN fails every comparison (so a check written "if abs(got - want) >
# tol: return <message>" passed it). Each chapter's right answers (the tests' RIGHT registries,
# or an answer of the right form below where a test file has none) are turned into strings,
# given a bool or a NaN, and every such variant must be "not yet — expected a ...".

PLACEHOLDER_ANSWERS = {  # answers of the right form, for the checks whose tests hold no RIGHT
    "mrclam": {
        "exercise_1": 0.88,
        "exercise_2": (1.5e-3, 2.5e-3),
        "exercise_3": (-1.25, "lower"),
        "exercise_4": (0.011, 0.052, 0.27),
    },
    "trabalho4": {
        "exercise_1": (512, 500.0),
        "exercise_2": (0.0, -1234.5),
        "exercise_3": 0.71,
        "exercise_4": 12.3,
        "exercise_5": (-3.2, -5.1),
        "exercise_6": 0.52,
    },
}
OWN_CHECKS = ("cir", "mcl", "mrclam", "trabalho3", "turkish")  # exercise_N called directly too


def _registry(short, name):
    test_file = TESTS / f"test_exercises_{short}.py"
    spec = importlib.util.spec_from_file_location(f"_right_answers_{short}", test_file)
    tests = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tests)
    return getattr(tests, name, None) or {}


def _is_number(x):
    return isinstance(x, int | float | np.integer | np.floating) and not isinstance(
        x, bool | np.bool_
    )


def _replace(value, new, first_only):
    """``value`` (nested tuples, lists, arrays of numbers) with ``new(x)`` for its numbers
    (or its first number only); arrays become lists. Returns (value, replaced anything)."""
    done = False

    def walk(v):
        nonlocal done
        if isinstance(v, np.ndarray):
            v = v.tolist()
        if isinstance(v, tuple | list):
            return type(v)(walk(item) for item in v)
        if _is_number(v) and not (first_only and done):
            done = True
            return new(v)
        return v

    return walk(value), done


def _non_numbers(right):
    """The string, bool and NaN variants of a right answer."""
    out = {}
    for label, new, first in [
        ("all strings", lambda x: repr(float(x)) if isinstance(x, float) else str(x), False),
        ("one string", lambda x: str(x), True),
        ("one True", lambda x: True, True),
        ("one False", lambda x: False, True),
        ("one NaN", lambda x: float("nan"), True),
        ("all NaN", lambda x: np.nan, False),
    ]:
        variant, replaced = _replace(right, new, first)
        if replaced:
            out[label] = variant
    if _is_number(right):
        out["numpy string"] = np.str_(repr(float(right)))
        out["numpy bool"] = np.bool_(bool(right))
    else:
        try:
            flat = np.asarray(right, dtype=float)
        except (TypeError, ValueError):  # ragged or holding words: the other variants do
            flat = None
        if flat is not None:
            out["array of strings"] = flat.astype(str)
    return out


def _non_number_cases():
    cases = []
    for short in sorted(set(CHAPTER_MODULES.values())):
        module = importlib.import_module(f"probrob.exercises.{short}")
        rights = {**PLACEHOLDER_ANSWERS.get(short, {}), **_registry(short, "RIGHT")}
        names = sorted(n for n in vars(module) if re.fullmatch(r"exercise_\d+", n))
        for name in names:
            assert name in rights, f"no right answer for {short}.{name}: add one above"
            for label, answer in _non_numbers(rights[name]).items():
                cases.append(pytest.param(short, name, answer, id=f"{short}.{name}-{label}"))
    return cases


@pytest.mark.parametrize(("short", "name", "answer"), _non_number_cases())
def test_a_string_a_bool_or_nan_is_never_correct(short, name, answer):
    module = importlib.import_module(f"probrob.exercises.{short}")
    test = getattr(module, name)
    line = verdict("E", answer, test=test)
    assert line.startswith("E: not yet — expected a"), (answer, line)
    if short in OWN_CHECKS:  # the chapter's own number reading refuses it too
        kwargs = {
            p.name: None
            for p in inspect.signature(test).parameters.values()
            if p.kind is p.KEYWORD_ONLY
        }
        message = test(answer, **kwargs)
        assert isinstance(message, str) and "expected a" in message, (answer, message)


def test_the_issue_examples_say_what_the_answer_is():
    from probrob.exercises import mcl

    assert (
        verdict("E", float("nan"), test=mcl.exercise_4)
        == "E: not yet — expected a number, got NaN"
    )
    assert verdict("E", (float("nan"), 0.0), test=mcl.exercise_5).startswith(
        "E: not yet — expected a number, got NaN"
    )
    assert "got a string" in verdict("E", "625", test=mcl.exercise_1)
    assert "got a string" in verdict(
        "E", (("0", "4", "1", "3"), (1, 5, 2, 4)), test=mcl.exercise_2
    )
    assert "got a bool" in verdict("E", (0.2, False), test=mcl.exercise_5)
    # words still reach a check that asks for one
    from probrob.exercises import mrclam

    assert "expected a" not in verdict("E", [1.0, "sideways"], test=lambda a: "checked")
    assert verdict("E", (1.0, "higher"), test=lambda a: None) == "E: correct"
    assert mrclam.exercise_3((1.0, 2.0), train=None, test=None).startswith("the second part")
