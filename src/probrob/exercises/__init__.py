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
4. the **solution**: a code cell tagged ``exercise-solution`` and ``hide-cell`` (code and
   output collapsed in the book, so the printed answer is hidden too; ``hide-input``
   collapses only the code) that computes the answer and calls the same check, which
   prints ``correct``. nbval re-runs it, so the tests prove that every exercise is solvable
   (``tests/test_exercises.py`` also checks that every solution prints "correct", is
   collapsed, and follows a check that prints "not yet" for the same exercise).

``check`` returns nothing (a trailing ``;`` does not silence a value under nbval);
:func:`verdict` returns the printed line.

Prefer a ``test`` that checks a property of the answer (by calling the library) to an
``expected`` value written into the check cell, which would give the answer away.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["check", "verdict"]


def _compare(answer, expected, rtol, atol):
    try:
        got = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
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
        when correct, else a string saying what is wrong (or ``False``).
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
                verdict = test(answer)
                if verdict is False:
                    problem = "the answer does not pass the check"
                elif isinstance(verdict, str):
                    problem = verdict
        except Exception as exc:
            problem = f"checking the answer raised {type(exc).__name__}: {exc}"
    if problem is None:
        return f"{name}: correct"
    return f"{name}: not yet — {problem}" + (f" (hint: {hint})" if hint else "")
