r"""Checks for the chapters' exercises: print "correct" or what is still wrong, never raise.

Holds :func:`check` and :func:`verdict`; each chapter's checks are a module of this package.
Does not hold any answer: a check computes the truth with the library.

The book's exercise pattern (every chapter copies it):

1. the task, in prose (a markdown cell);
2. an **answer cell** that runs as shipped, with a starting line that fails the check,
   e.g. ``alpha_95 = None  # your answer``;
3. a **check cell** (tag ``exercise-check``), ``check("Exercise 3", alpha_95, test=...)``:
   it prints ``Exercise 3: correct`` or what is wrong, and never raises, so that nbval and
   the book build stay green while the exercise is unsolved (as shipped it prints
   ``Exercise 3: not yet — ...``);
4. the **solution**, right after the check: a markdown cell (tag ``exercise-solution``)
   holding a collapsed box, ``:::{dropdown} Solution to Exercise 3``, with the code that
   computes the answer and calls the same check. Being markdown, it is not run by
   JupyterLab's *Run All* (the reader's exercise stays the reader's), and the book shows it
   collapsed. ``tests/test_exercises.py`` checks this form and that the check cell holds no
   answer; ``tests/test_exercise_solutions.py`` runs every chapter with each solution pasted
   in after its check and requires "correct", so every exercise is known to be solvable.

``check`` returns nothing (a trailing ``;`` does not silence a value under nbval);
:func:`verdict` returns the printed line.

Prefer a ``test`` that checks a property of the answer (by calling the library) to an
``expected`` value written into the check cell, which would give the answer away.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .. import _validation

__all__ = ["check", "verdict"]


def _compare(answer, expected, rtol, atol):
    # Real numbers only: a string "4", a complex 4+1j or a bool is not a number (numpy
    # would read "4" as 4.0 and drop the imaginary part of 4+1j, calling both correct).
    try:
        got = _validation.as_float_array(answer, "answer")
        is_bool = np.asarray(answer).dtype == bool
    except (TypeError, ValueError):
        is_bool, got = False, None
    if got is None or is_bool:
        return f"expected a number or an array of numbers, got {type(answer).__name__}"
    want = np.asarray(expected, dtype=float)
    if got.shape != want.shape:
        return f"expected shape {want.shape}, got shape {got.shape}"
    if not np.all(np.isfinite(got)):
        return "the answer contains NaN or infinity"
    if np.allclose(got, want, rtol=rtol, atol=atol):
        return None
    if got.size == 1:
        return "too large" if float(got) > float(want) else "too small"
    bad = int(np.sum(~np.isclose(got, want, rtol=rtol, atol=atol)))
    return f"{bad} of {got.size} values are off"


def _test_problem(result) -> str | None:
    """What a ``test`` callable's ``result`` says is wrong, or ``None`` when it says correct.

    Only ``None``, ``True`` (a Python or numpy bool) and a non-empty array of bools that
    are all true mean correct; a string is the message (an empty one is a plain "no"). Any
    other result (``False``, ``0``, ``np.array([False])``, a number, an empty array) is
    "not yet": a falsy value must never pass as correct.
    """
    if result is None:
        return None
    if isinstance(result, str):
        return result or "the answer does not pass the check"
    if isinstance(result, bool | np.bool_):
        return None if result else "the answer does not pass the check"
    if isinstance(result, np.ndarray) and result.dtype == bool:
        if result.size and result.all():
            return None
        return "the answer does not pass the check"
    return (
        f"the check returned {type(result).__name__} {_short(result)}, not None, True, False "
        "or a message"
    )


def _short(value, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 4] + " ..."


def check(
    name: str,
    answer,
    expected=None,
    *,
    test: Callable | None = None,
    rtol: float = 1e-6,
    atol: float = 0.0,
    hint: str | None = None,
) -> None:
    """Print ``"<name>: correct"`` or ``"<name>: not yet — <what is wrong>"``.

    Never raises: an answer that is missing (``None`` or ``...``), of the wrong type or
    shape, or that makes ``test`` fail or raise, is reported in the printed line.

    Parameters
    ----------
    name : str
        The exercise's name, printed first (e.g. ``"Exercise 3"``).
    answer : object
        The reader's answer.
    expected : array_like, optional
        The value the answer must equal within ``rtol``/``atol`` (``numpy.allclose``).
        The printed message says only "too large" / "too small", never the value.
    test : callable, optional
        ``test(answer)`` for answers checked by a property: returns ``None`` or ``True``
        (also a numpy bool, or an array of bools all true) when correct, else a string
        saying what is wrong (or ``False``). Anything else, ``0`` or
        ``np.array([False])`` included, counts as wrong.
    rtol, atol : float
        Tolerances for ``expected``.
    hint : str, optional
        Appended to the message when the answer is wrong.

    Returns
    -------
    None
        Nothing, so that a check as the last line of a cell shows only its message (a
        trailing ``;`` does not silence a value under nbval). Use :func:`verdict` for
        the message as a value.
    """
    print(verdict(name, answer, expected, test=test, rtol=rtol, atol=atol, hint=hint))


def verdict(
    name: str,
    answer,
    expected=None,
    *,
    test: Callable | None = None,
    rtol: float = 1e-6,
    atol: float = 0.0,
    hint: str | None = None,
) -> str:
    """Return the line that :func:`check` prints (same arguments); never raise."""
    if answer is None or answer is Ellipsis:
        problem = "no answer yet: replace the starting line with your answer"
    else:
        try:
            problem = None
            if expected is not None:
                problem = _compare(answer, expected, rtol, atol)
            if problem is None and test is not None:
                problem = _test_problem(test(answer))
        except Exception as exc:
            problem = f"checking the answer raised {type(exc).__name__}: {exc}"
    if problem is None:
        return f"{name}: correct"
    return f"{name}: not yet — {problem}" + (f" (hint: {hint})" if hint else "")
