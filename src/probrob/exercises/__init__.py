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

One rule of digits for every chapter: an answer right to the check's tolerance passes; an
answer that is the truth rounded (or cut) to too few digits is told to give more digits
(:func:`more_digits`), not the concept message, which is for answers that are wrong; a
typical wrong value typed with few digits is still recognised (:func:`agrees`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .. import _validation

__all__ = ["agrees", "check", "more_digits", "not_a_number", "one_number", "verdict"]


def _kinds(answer, depth: int = 0):
    """What each entry of ``answer`` is, walking tuples, lists and arrays: yields
    ``"number"``, ``"nan"``, ``"inf"``, ``"bool"``, ``"complex"``, ``"numeric string"``,
    ``"word"``, ``"None"`` or the type name of anything else (a function, a dict)."""
    if isinstance(answer, np.ndarray) and answer.dtype.kind in "biufc":
        kind = answer.dtype.kind
        if kind == "b" and answer.size:
            yield "bool"
        elif kind == "c" and answer.size:
            yield "complex"
        elif kind == "f" and not np.all(np.isfinite(answer)):
            yield "nan" if np.any(np.isnan(answer)) else "inf"
        else:
            yield "number"
        return
    if isinstance(answer, tuple | list | np.ndarray) and depth < 20:
        for item in answer:
            yield from _kinds(item, depth + 1)
        return
    if isinstance(answer, bool | np.bool_):
        yield "bool"
    elif isinstance(answer, complex | np.complexfloating):
        yield "complex"
    elif isinstance(answer, int | float | np.integer | np.floating):
        value = float(answer) if not isinstance(answer, int) else 0.0
        yield "number" if np.isfinite(value) else ("nan" if np.isnan(value) else "inf")
    elif isinstance(answer, str | bytes):
        try:
            float(answer)
        except ValueError:
            yield "word"
        else:
            yield "numeric string"
    elif answer is None:
        yield "None"
    else:
        yield type(answer).__name__


_NOT_A_NUMBER = {
    "bool": "expected a number, got a bool (True or False)",
    "complex": "expected a real number, got a complex number",
    "nan": "expected a number, got NaN",
    "inf": "expected a finite number, got infinity",
    "numeric string": "expected a number, got a string (remove the quotes)",
    "word": "expected a number, got a string",
    "None": "expected a number, got None",
}


def not_a_number(answer) -> str | None:
    """Return why ``answer`` is not a number (or nested tuples, lists or arrays of numbers),
    or ``None`` if it is.

    A string (``"625"``, even though numpy would read it as 625.0), a bool (``True`` is not
    1), NaN, infinity, a complex number, ``None`` or any other object, anywhere in the answer,
    is not a number. The message says which, never what the right answer is; shapes are
    the caller's to check.

    Examples
    --------
    >>> not_a_number((0.3, 4)) is None
    True
    >>> not_a_number(("0", "4"))
    'expected a number, got a string (remove the quotes)'
    >>> not_a_number((0.3, False))
    'expected a number, got a bool (True or False)'
    """
    for kind in _kinds(answer):
        if kind != "number":
            return _NOT_A_NUMBER.get(kind, f"expected a number, got {kind}")
    return None


def one_number(answer, what: str = "one number") -> tuple[float | None, str | None]:
    """Return ``(value, None)`` if ``answer`` is one real finite number, else ``(None, why)``.

    ``why`` is :func:`not_a_number`'s message, or ``"expected <what>, got shape ..."`` for an
    array or a sequence of numbers.

    Examples
    --------
    >>> one_number(2.5)
    (2.5, None)
    >>> one_number([1, 2], "one probability")
    (None, 'expected one probability, got shape (2,)')
    """
    problem = not_a_number(answer)
    if problem:
        return None, problem
    value = np.asarray(answer, dtype=float)
    if value.shape != ():
        return None, f"expected {what}, got shape {value.shape}"
    return float(value), None


def _last_digit(value: float) -> tuple[float, int]:
    """The place value of the last digit of ``value`` as typed (its shortest decimal form)
    and its number of significant digits: 0.0016 -> (1e-4, 2), 625 -> (1, 3), 630 -> (10, 2).

    Trailing zeros of a whole number are not counted as significant (630 may be 625 rounded).
    """
    text = np.format_float_positional(abs(value), unique=True, trim="-")
    whole, _, decimals = text.partition(".")
    if decimals:
        return 10.0 ** -len(decimals), len((whole + decimals).lstrip("0"))
    stripped = whole.rstrip("0")
    return 10.0 ** (len(whole) - len(stripped)), len(stripped)


def _within(got: np.ndarray, want: np.ndarray, rtol: float, atol: float) -> np.ndarray:
    with np.errstate(over="ignore", invalid="ignore"):
        return np.abs(got - want) <= atol + rtol * np.abs(want)


def _rounded_from(got: float, want: float) -> bool:
    """Whether ``got`` is ``want`` rounded or cut to the digits ``got`` shows (at least two)."""
    unit, digits = _last_digit(got)
    if digits < 2:
        return False
    diff = abs(got - want)
    rounded = diff <= 0.5 * unit * (1 + 1e-9)  # the unit is a decimal, not exact in binary
    cut = got * want > 0 and abs(got) <= abs(want) and diff < unit
    return bool(rounded or cut)


def _as_pair(answer, truth):
    """``answer`` and ``truth`` as broadcast float arrays, or ``None`` if they are not numbers
    of one shape (the caller's own checks report that)."""
    if not_a_number(answer) is not None:
        return None
    try:
        got = _validation.as_float_array(answer, "answer")
        want = _validation.as_float_array(truth, "truth")
    except (TypeError, ValueError):
        return None
    if got.shape != want.shape and got.size != 1 and want.size != 1:
        return None
    got, want = np.broadcast_arrays(got, want)
    if not (np.all(np.isfinite(got)) and np.all(np.isfinite(want))):
        return None
    return got, want


def _digits_needed(want: np.ndarray, rtol: float, atol: float) -> int:
    """The fewest significant digits to which every value of ``want``, rounded, is within the
    tolerance."""
    for n in range(1, 18):
        rounded = np.array([float(f"{w:.{n - 1}e}") for w in want.ravel()])
        if np.all(_within(rounded, want.ravel(), rtol, atol)):
            return n
    return 17


def more_digits(answer, truth, *, rtol=1e-6, atol=0.0) -> str | None:
    r"""Return "close, but give more digits ..." when ``answer`` is ``truth`` rounded (or cut)
    to fewer digits than the check needs; ``None`` otherwise.

    The shared rule of every chapter's checks: an answer right to the check's tolerance
    (``|answer - truth| <= atol + rtol |truth|``, as :func:`numpy.isclose`) passes; one that
    shows at least two significant digits, each of them the truth's (rounded or cut at its
    last digit), but misses the tolerance, is told to give more digits, and how many; any
    other answer is wrong, and gets the chapter's concept message. Use it where a check has
    found that the answer is not right::

        if not np.isclose(got, truth, rtol=1e-4):
            return more_digits(got, truth, rtol=1e-4) or "the variance is off: ..."

    The message never shows the truth, only how many significant digits pass.

    Parameters
    ----------
    answer : array_like
        The reader's answer: a number or an array of numbers (anything else gives ``None``).
    truth : array_like, same shape as ``answer`` (or a scalar)
        The right value(s), computed by the check.
    rtol, atol : float
        The check's own tolerances, as it compares ``answer`` with ``truth``.

    Returns
    -------
    str or None
        The message when every value of ``answer`` is right or short of digits, and at least
        one is short of digits; ``None`` when the answer is right, wrong, or not numbers.

    Examples
    --------
    >>> more_digits(0.31, 0.3125, rtol=1e-6)
    'close, but give more digits: the check needs 4 significant digits'
    >>> more_digits(0.3125, 0.3125) is None  # right
    True
    >>> more_digits(0.2, 0.3125) is None  # wrong (and 0.3 has one digit only)
    True
    """
    pair = _as_pair(answer, truth)
    if pair is None:
        return None
    got, want = pair
    ok = _within(got, want, rtol, atol)
    if ok.all():
        return None
    if not all(_rounded_from(g, w) for g, w in zip(got[~ok], want[~ok], strict=True)):
        return None
    n = _digits_needed(want, rtol, atol)
    return f"close, but give more digits: the check needs {n} significant digits"


def agrees(answer, value, *, rtol=1e-6, atol=0.0) -> bool:
    """Whether ``answer`` is ``value`` to the tolerance, or ``value`` rounded or cut to the
    (at least two significant) digits the answer shows.

    For recognising a typical *wrong* value (the deck's formula, a variance for a standard
    deviation) also when the reader typed it with a few digits, so that the concept message
    still applies: ``if agrees(got, np.sqrt(truth)): return "that is a standard deviation"``.
    Not for the right answer: a right value short of digits is :func:`more_digits`'s case.

    Parameters
    ----------
    answer, value : array_like, same shape (or scalars)
    rtol, atol : float
        Tolerances as :func:`numpy.isclose`.

    Returns
    -------
    bool
        ``False`` also when ``answer`` is not numbers.
    """
    pair = _as_pair(answer, value)
    if pair is None:
        return False
    got, want = pair
    ok = _within(got, want, rtol, atol)
    return bool(all(_rounded_from(g, w) for g, w in zip(got[~ok], want[~ok], strict=True)))


def _screen(answer) -> str | None:
    """What :func:`verdict` refuses before any check sees the answer: a string that reads as
    a number (``"625"``), a bool, NaN, infinity or a complex number, anywhere in it. Words
    (``"higher"``), functions and other objects go on to the check, which knows whether it
    asked for them."""
    for kind in _kinds(answer):
        if kind in ("numeric string", "bool", "nan", "inf", "complex"):
            return _NOT_A_NUMBER[kind]
    return None


def _compare(answer, expected, rtol, atol):
    # Real numbers only: a string "4", a complex 4+1j or a bool is not a number (numpy
    # would read "4" as 4.0 and drop the imaginary part of 4+1j, calling both correct).
    problem = not_a_number(answer)
    if problem:
        return problem
    try:
        got = _validation.as_float_array(answer, "answer")
    except (TypeError, ValueError):
        return f"expected a number or an array of numbers, got {type(answer).__name__}"
    want = np.asarray(expected, dtype=float)
    if got.shape != want.shape:
        return f"expected shape {want.shape}, got shape {got.shape}"
    if not np.all(np.isfinite(got)):
        return "the answer contains NaN or infinity"
    if np.allclose(got, want, rtol=rtol, atol=atol):
        return None
    short = more_digits(got, want, rtol=rtol, atol=atol)
    if short:
        return short
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
    shape, or that makes ``test`` fail or raise, is reported in the printed line. A string
    that reads as a number (``"625"``), a bool, NaN, infinity or a complex number anywhere in
    the answer is never correct: it is reported ("expected a number, got a string") before
    ``test`` or ``expected`` sees it, for every chapter's checks.

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
            problem = _screen(answer)
            if problem is None and expected is not None:
                problem = _compare(answer, expected, rtol, atol)
            if problem is None and test is not None:
                problem = _test_problem(test(answer))
        except Exception as exc:
            problem = f"checking the answer raised {type(exc).__name__}: {exc}"
    if problem is None:
        return f"{name}: correct"
    return f"{name}: not yet — {problem}" + (f" (hint: {hint})" if hint else "")
