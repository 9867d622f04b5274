r"""The one validation layer of probrob: every public function checks its input here.

Holds every argument check of the public functions, and the overflow report.
Does not hold models or what they compute; no other module defines its own checks.

Rules (the book's *conventions* page, section "What the library accepts"):

* bad input raises ``ValueError`` whose message names the argument (and its value or shape);
  complex input raises ``TypeError`` naming the argument, never a silent cast to real;
* the batch (leading) shapes of all array arguments are checked together, up front, by
  :func:`batch_shape`, so a mismatch names every argument and its shape;
* ``rng`` goes through :func:`rng` (``None``, a non-negative int, a
  :class:`numpy.random.SeedSequence` or a :class:`numpy.random.Generator`), ``size`` through
  :func:`size_shape` (an int or a tuple of ints);
* a computation that overflows float64 although every input was finite is reported by
  :func:`no_overflow` against the caller's own arguments, never as ``OverflowError``,
  ``RuntimeWarning`` or an internal variable name.

Typical use in a library function::

    from . import _validation as check


    def my_model(x, u, alpha, *, size=None, rng=None):
        x = check.poses(x, "x")  # (..., 3), finite, real
        u = check.vectors(u, "u", 2, "v, omega")
        alpha = check.alphas(alpha, "alpha", 4)  # (4,), finite, >= 0
        batch = check.batch_shape(x=x.shape[:-1], u=u.shape[:-1])
        shape = check.output_shape(batch, size)
        gen = check.rng(rng)
        ...
        check.no_overflow(result, "my_model's result", x=x, u=u)

All helpers return numpy ``float64`` arrays (or Python scalars where stated) and never modify
their argument.
"""

from __future__ import annotations

import functools
import math
import operator

import numpy as np
from scipy.linalg.lapack import dpotrf as _dpotrf

_REAL_KINDS = "biuf"  # bool, signed and unsigned integers, floats
_FLOAT64 = np.dtype(np.float64)
_FEW = 64  # up to this many numbers, a Python loop beats a numpy call (its overhead ~1 µs)


def _short(value, limit: int = 120) -> str:
    """``repr(value)``, cut to ``limit`` characters (a message must stay readable).

    A numpy scalar shows as the Python number (``0.6``, not ``np.float64(0.6)``).
    """
    if isinstance(value, np.generic):
        value = value.item()
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 5] + " ...]"


# --------------------------------------------------------------------------- arrays


def as_float_array(value, name: str) -> np.ndarray:
    """Return ``value`` as a ``float64`` array (no copy if it already is one).

    Raises ``TypeError`` naming ``name`` for complex input (``np.asarray(z, float)`` would
    silently drop the imaginary part), and ``ValueError`` naming ``name`` for anything that is
    not numeric (``None``, strings, ragged nested lists, objects).
    """
    if type(value) is np.ndarray and value.dtype is _FLOAT64:  # the common case, fast
        return value
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise ValueError(f"{name} must be numeric array_like, got {_short(value)}") from exc
    kind = arr.dtype.kind
    if kind == "c":
        raise TypeError(f"{name} must be real, got complex input {_short(value)}")
    if kind in _REAL_KINDS:
        if kind == "f" and arr.dtype.itemsize > 8:  # long double: inf where it overflows
            with np.errstate(over="ignore"):
                return arr.astype(float)
        return arr.astype(float, copy=False)
    if kind == "O":
        if any(isinstance(item, complex) for item in arr.flat):
            raise TypeError(f"{name} must be real, got complex input {_short(value)}")
        if any(item is None for item in arr.flat):
            raise ValueError(f"{name} must be numeric array_like, got {_short(value)}")
    if kind != "O":  # strings, bytes, datetimes, structured arrays
        raise ValueError(f"{name} must be numeric array_like, got {_short(value)}")
    try:
        return arr.astype(float)
    except OverflowError as exc:  # a Python int beyond float64
        raise ValueError(f"{name} is out of the float64 range, got {_short(value)}") from exc
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric array_like, got {_short(value)}") from exc


array = as_float_array


def all_finite(arr: np.ndarray) -> bool:
    """Whether every entry of a float array is finite (fast: one reduction in the common case)."""
    if arr.size <= _FEW:
        # A few numbers: their sum in Python floats (which overflow to inf silently) costs
        # less than entering np.errstate for one reduction.
        finite_sum = math.isfinite(sum(arr.ravel().tolist(), 0.0))
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            finite_sum = bool(np.isfinite(np.add.reduce(arr, axis=None)))
    # A finite sum proves every entry finite; an infinite one may be a sum that overflowed.
    return finite_sum or bool(np.isfinite(arr).all())


def _min(arr: np.ndarray):
    """The smallest entry of a non-empty array (a Python loop for a few numbers)."""
    return min(arr.ravel().tolist()) if arr.size <= _FEW else arr.min()


def _max(arr: np.ndarray):
    """The largest entry of a non-empty array (a Python loop for a few numbers)."""
    return max(arr.ravel().tolist()) if arr.size <= _FEW else arr.max()


def finite(value, name: str) -> np.ndarray:
    """Return a finite float array; NaN or ±inf raise ``ValueError`` naming ``name``."""
    arr = as_float_array(value, name)
    if not all_finite(arr):
        bad = float(arr[~np.isfinite(arr)].flat[0])
        raise ValueError(f"{name} must be finite (no NaN or inf), got {bad!r} in it")
    return arr


def variance(value, name: str = "b2") -> np.ndarray:
    """Return a finite, non-negative float array of variances."""
    arr = as_float_array(value, name)
    if np.any(np.isnan(arr)):
        raise ValueError(f"{name} must not be NaN")
    if np.any(arr < 0):
        raise ValueError(f"{name} is a variance and must be >= 0, got min {_short(arr.min())}")
    if np.any(np.isinf(arr)):
        raise ValueError(f"{name} must be finite")
    return arr


def vectors(value, name: str, length: int, what: str) -> np.ndarray:
    """Return a finite array whose last axis has ``length`` entries."""
    arr = finite(value, name)
    if arr.ndim == 0 or arr.shape[-1] != length:
        raise ValueError(f"{name} must have shape (..., {length}) ({what}), got shape {arr.shape}")
    return arr


def poses(value, name: str) -> np.ndarray:
    """Return a finite pose array of shape ``(..., 3)``."""
    return vectors(value, name, 3, "x, y, theta")


def single_pose(value, name: str) -> np.ndarray:
    """Return one finite pose, shape ``(3,)`` exactly (e.g. for drawing a single arrow)."""
    arr = finite(value, name)
    if arr.shape != (3,):
        raise ValueError(
            f"{name} must be one pose (x, y, theta) of shape (3,), got shape {arr.shape}"
        )
    return arr


def alphas(value, name: str, count: int) -> np.ndarray:
    """Return ``count`` finite, non-negative noise parameters as a ``(count,)`` array."""
    arr = finite(value, name)
    if arr.shape != (count,):
        raise ValueError(f"{name} must hold {count} values (α1..α{count}), got shape {arr.shape}")
    if _min(arr) < 0:
        raise ValueError(f"{name} must be non-negative, got {arr.tolist()}")
    return arr


def positive_scalar(value, name: str) -> float:
    """Return a finite, strictly positive float."""
    if type(value) is float and 0.0 < value < math.inf:  # the common case, fast
        return value
    arr = finite(value, name)
    if arr.ndim != 0 or not arr > 0:
        raise ValueError(f"{name} must be a positive scalar, got {_short(value)}")
    return float(arr)


def real_scalar(value, name: str) -> float:
    """Return one finite float (a number or a 0-d array; ``[x]`` is not a scalar)."""
    if type(value) is float and math.isfinite(value):  # the common case, fast
        return value
    arr = finite(value, name)
    if arr.ndim != 0:
        raise ValueError(f"{name} must be a number, got shape {arr.shape}: {_short(value)}")
    return float(arr)


def in_range(value, name: str, lo: float, hi: float) -> float:
    """Return a finite float scalar in the closed interval ``[lo, hi]`` (never clamped)."""
    arr = finite(value, name)
    if arr.ndim != 0 or not lo <= arr <= hi:
        raise ValueError(f"{name} must be a number in [{lo}, {hi}], got {_short(value)}")
    return float(arr)


def count(value, name: str, minimum: int = 0) -> int:
    """Return an integer ``>= minimum`` (a bool or a float such as 2.7 is rejected, not truncated)."""
    if isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} must be an integer, got {_short(value)}")
    try:
        n = operator.index(value)
    except TypeError as exc:
        raise ValueError(f"{name} must be an integer, got {_short(value)}") from exc
    if n < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {_short(value)}")
    return n


def choice(value, name: str, options: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``options``."""
    try:
        ok = value in options
    except TypeError:  # e.g. an unhashable or array-valued argument
        ok = False
    if not ok or not isinstance(value, str):
        raise ValueError(f"{name} must be one of {options}, got {_short(value)}")
    return value


def callable_arg(value, name: str):
    """Return ``value`` if it is callable."""
    if not callable(value):
        raise ValueError(f"{name} must be callable, got {_short(value)}")
    return value


def scalar_or_array(arr: np.ndarray):
    """Return a Python float for a 0-d array, the array otherwise (scalars in, scalars out)."""
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr


# --------------------------------------------------------------------------- shapes


def batch_shape(**shapes: tuple[int, ...]) -> tuple[int, ...]:
    """Return the broadcast of the named batch shapes, or raise naming each argument.

    ``batch_shape(x_t=x_t.shape[:-1], u_t=u_t.shape[:-1])``: call it before any arithmetic,
    so that a mismatch says which arguments disagree instead of numpy's "operands could not
    be broadcast together" from deep inside.
    """
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        listed = ", ".join(f"{name} {tuple(shape)}" for name, shape in shapes.items())
        raise ValueError(
            f"the batch shapes of the arguments do not broadcast together: {listed} "
            "(leading axes must be equal or 1, as in numpy broadcasting)"
        ) from None


def size_shape(size, name: str = "size") -> tuple[int, ...] | None:
    """Normalise a numpy-style ``size`` (None, an int, or a tuple of ints) to a shape tuple.

    Floats (``2.7``), bools and strings are rejected, not truncated.
    """
    if size is None:
        return None
    if isinstance(size, bool | np.bool_ | str | bytes):
        raise ValueError(f"{name} must be None, an int or a tuple of ints, got {size!r}")
    try:
        shape = (operator.index(size),)
    except TypeError:
        try:
            items = tuple(size)
        except TypeError:
            items = None
        if items is None or any(isinstance(n, bool | np.bool_) for n in items):
            raise ValueError(
                f"{name} must be None, an int or a tuple of ints, got {size!r}"
            ) from None
        try:
            shape = tuple(operator.index(n) for n in items)
        except TypeError:
            raise ValueError(
                f"{name} must be None, an int or a tuple of ints, got {size!r}"
            ) from None
    if any(n < 0 for n in shape):
        raise ValueError(f"{name} must not be negative, got {size!r}")
    return shape


def output_shape(batch: tuple[int, ...], size, name: str = "size") -> tuple[int, ...]:
    """Shape of a sampler's output: ``size`` if given (``batch`` must broadcast to it)."""
    shape = size_shape(size, name)
    if shape is None:
        return batch
    try:
        full = np.broadcast_shapes(batch, shape)
    except ValueError:
        full = None
    if full != shape:
        raise ValueError(f"{name} {shape} is not compatible with the input batch shape {batch}")
    return shape


# --------------------------------------------------------------------------- randomness


def rng(value, name: str = "rng") -> np.random.Generator:
    """Return a ``numpy.random.Generator`` for ``value``.

    Accepted: ``None`` (fresh OS entropy), a non-negative int seed, a
    :class:`numpy.random.SeedSequence`, or a :class:`numpy.random.Generator` (returned as is,
    so successive calls continue its stream). Anything else raises ``ValueError`` naming
    ``rng``.
    """
    if value is None or isinstance(value, np.random.SeedSequence):
        return np.random.default_rng(value)
    if isinstance(value, np.random.Generator):
        return value
    if isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_):
        if value < 0:
            raise ValueError(f"{name} must be a non-negative int seed, got {_short(value)}")
        return np.random.default_rng(int(value))
    raise ValueError(
        f"{name} must be None, a non-negative int, a numpy.random.SeedSequence or a "
        f"numpy.random.Generator, got {_short(value)}"
    )


def _returned_array(value, name: str) -> np.ndarray:
    """``value`` returned by the user's callable ``name`` as a float array, or an error naming it."""
    try:
        return as_float_array(value, f"the value returned by {name}")
    except TypeError as exc:
        raise TypeError(f"{name} must return real numbers: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"{name} must return real numbers: {exc}") from None


def sample_output(value, name: str, shape: tuple[int, ...], func=None) -> np.ndarray:
    """Check what a user's ``sample`` returned: finite real numbers broadcastable to ``shape``.

    Any real dtype is accepted and returned as ``float64`` (a copy only if it is not float64
    already). The caller must not modify the result in place unless it made the copy itself.
    ``func``, the callable itself, is named in the message (a NaN it returns is its fault,
    not that of the noise parameters).
    """
    name = _callable_label(name, func)
    arr = _returned_array(value, name)
    try:
        full = np.broadcast_shapes(arr.shape, shape)
    except ValueError:
        full = None
    if full != shape:
        raise ValueError(
            f"{name} returned shape {arr.shape}, which does not broadcast to the requested "
            f"size {shape}"
        )
    _returned_finite(arr, name)
    return arr


# --------------------------------------------------------------------------- overflow


def _extremeness(value) -> float:
    """How far from 1 the most extreme non-zero magnitude in ``value`` is, in decades."""
    mags = np.abs(np.asarray(value, dtype=float)).ravel()
    mags = mags[(mags > 0) & np.isfinite(mags)]
    return float(np.max(np.abs(np.log10(mags)))) if mags.size else 0.0


def _show(value) -> str:
    arr = np.asarray(value)
    if arr.ndim == 0:
        return repr(float(arr)) if arr.dtype.kind == "f" else repr(value)
    return np.array2string(arr, precision=6, threshold=12)


def overflow_error(what: str, index=None, **arguments) -> ValueError:
    """The ``ValueError`` for a float64 overflow in ``what``, blaming the caller's arguments.

    ``arguments`` maps the caller's argument names to the values involved (already indexed
    at the offending batch element, if any). The argument with the most extreme magnitude
    (largest or smallest in decades) is named as the culprit; all are listed.
    """
    culprit = max(arguments, key=lambda k: _extremeness(arguments[k]))
    where = "" if index is None or index == () else f" (batch element {index})"
    listed = ", ".join(f"{name} = {_show(value)}" for name, value in arguments.items())
    return ValueError(
        f"{culprit} = {_show(arguments[culprit])} is out of range: {what} overflows "
        f"float64{where}; got {listed}"
    )


def no_overflow(values, what: str, **arguments) -> None:
    """Raise :func:`overflow_error` if ``values`` (computed from finite input) is not finite.

    ``arguments`` are the caller's own (validated) arguments that ``values`` was computed
    from, by the names the caller used; the message names the most extreme of them and
    shows all, with the batch index of the first non-finite entry of ``values``.
    """
    values = np.asarray(values)
    if all_finite(values):
        return
    index = tuple(int(i) for i in np.argwhere(~np.isfinite(values))[0])
    raise overflow_error(what, index, **arguments)


def callable_result(
    value, name: str, shape: tuple[int, ...] | None = None, func=None
) -> np.ndarray:
    """Check an array returned by a user's callable (e.g. ``prob``): real, numeric, no NaN.

    With ``shape`` (that of the arguments it was given, broadcast), the result must broadcast
    to it: a ``prob`` that returns 7 values for 4 points is an error naming ``name``. ``func``,
    the callable itself, is named in the message too.
    """
    name = _callable_label(name, func)
    arr = _returned_array(value, name)
    if shape is not None:
        try:
            full = np.broadcast_shapes(arr.shape, shape)
        except ValueError:
            full = None
        if full != tuple(shape):
            raise ValueError(
                f"{name} returned shape {arr.shape} for arguments of shape {tuple(shape)}: it "
                "must return one value per point"
            )
    if np.isnan(arr).any():
        raise ValueError(f"{name} returned NaN")
    return arr


__all__ = [
    "alphas",
    "array",
    "as_float_array",
    "batch_shape",
    "callable_arg",
    "callable_result",
    "choice",
    "count",
    "finite",
    "flag",
    "in_range",
    "no_overflow",
    "output_shape",
    "overflow_error",
    "poses",
    "positive_scalar",
    "real_scalar",
    "rng",
    "sample_output",
    "scalar_or_array",
    "single_pose",
    "size_shape",
    "variance",
    "vectors",
]


def flag(value, name: str) -> bool:
    """Return ``value`` if it is a bool (``True``/``False``, numpy bools too)."""
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} must be True or False, got {_short(value)}")
    return bool(value)


# --------------------------------------------------------------------------- user callables
# (issue 15: what a user's callable returns is checked, and the message names the callable)


def _callable_label(name: str, func) -> str:
    """``"sample"`` or ``"sample (my_sampler)"``: the argument, and the callable's own name."""
    if func is None:
        return name
    inner = func
    while isinstance(inner, functools.partial):
        inner = inner.func
    label = getattr(inner, "__qualname__", None) or type(inner).__name__
    if inner is not func:
        label = f"functools.partial({label}, ...)"
    return f"{name} ({label})"


def _returned_finite(arr: np.ndarray, name: str) -> None:
    """A sampler's draws must be finite: NaN or ±inf from ``name`` is its own error."""
    if not all_finite(arr):
        bad = float(arr[~np.isfinite(arr)].flat[0])
        raise ValueError(
            f"{name} returned {bad!r}: a sampler must return finite draws "
            f"({int((~np.isfinite(arr)).sum())} of {arr.size} are not)"
        )


# --------------------------------------------------------------------------- filters
# The arguments of the Gaussian filters (probrob.localization), their evaluation
# (probrob.evaluation) and the noise fits (probrob.fitting).


def vector(value, name: str, length: int, what: str) -> np.ndarray:
    """Return one finite vector of shape ``(length,)`` exactly (e.g. one control ``u``)."""
    arr = finite(value, name)
    if arr.shape != (length,):
        raise ValueError(f"{name} must have shape ({length},) ({what}), got shape {arr.shape}")
    return arr


def open_probability(value, name: str) -> float:
    """Return a float scalar in the open interval (0, 1)."""
    arr = finite(value, name)
    if arr.ndim != 0 or not 0.0 < arr < 1.0:
        raise ValueError(f"{name} must be a probability in (0, 1), got {_short(value)}")
    return float(arr)


def covariance(value, name: str, sizes: tuple[int, ...] = (3,), *, stack: bool = False):
    """Return a finite, symmetric, positive semi-definite covariance matrix.

    Shape ``(n, n)`` with ``n`` in ``sizes``; with ``stack=True`` also ``(..., n, n)``.
    Symmetric means equal to its transpose to ``1e-12 + 1e-9 |S_ij|`` (never symmetrised
    silently); positive semi-definite means no eigenvalue below ``-1e-12`` times the
    largest (singular is legal: ``0`` is a known pose).
    """
    S = finite(value, name)
    n = S.shape[-1] if S.ndim >= 2 else None
    if S.ndim < 2 or (S.ndim > 2 and not stack) or S.shape[-2] != n or n not in sizes:
        shapes = " or ".join(f"({'..., ' if stack else ''}{k}, {k})" for k in sizes)
        raise ValueError(f"{name} must have shape {shapes}, got {S.shape}")
    ST = S.swapaxes(-1, -2)
    exactly = S.tolist() == ST.tolist() if S.size <= _FEW else (S == ST).all()
    if not exactly and not np.all(np.abs(S - ST) <= 1e-12 + 1e-9 * np.abs(ST)):
        where = tuple(int(k) for k in np.argwhere(np.abs(S - ST) > 1e-12 + 1e-9 * np.abs(ST))[0])
        *batch, i, j = where
        raise ValueError(
            f"{name} must be symmetric, got entry {where} = {float(S[where])!r} and "
            f"{(*batch, j, i)} = {float(S[(*batch, j, i)])!r}"
        )
    if not is_positive_semidefinite(S):
        eig = np.linalg.eigvalsh(S)
        raise ValueError(
            f"{name} is not positive semi-definite (smallest eigenvalue {eig.min():.3g})"
        )
    return S


def is_positive_semidefinite(S: np.ndarray) -> bool:
    """Whether the symmetric ``S`` (..., n, n) is positive semi-definite: no eigenvalue below
    ``-1e-12`` times the largest (a Cholesky factor, when it exists, proves it cheaply)."""
    if S.ndim == 2:  # one matrix: LAPACK's Cholesky directly (np.linalg's checks cost more)
        if _dpotrf(S, lower=1)[1] == 0:
            return True
    else:
        try:
            np.linalg.cholesky(S)
            return True
        except np.linalg.LinAlgError:
            pass
    eig = np.linalg.eigvalsh(S)
    return bool(np.all(eig[..., 0] >= -1e-12 * np.maximum(1.0, eig[..., -1])))


def landmark_map(value, name: str = "m") -> np.ndarray:
    """Return a finite, non-empty landmark map of shape ``(L, 3)``: rows ``(x, y, s)``."""
    m = finite(value, name)
    if m.ndim != 2 or m.shape[1] != 3:
        raise ValueError(f"{name} must have shape (L, 3) (landmark x, y, s), got {m.shape}")
    if m.shape[0] == 0:
        raise ValueError(f"{name} is an empty map: it needs at least one landmark")
    return m


def features(value, name: str = "z") -> np.ndarray:
    """Return a step's features as ``(K, 3)`` rows ``(r, phi, s)`` or ``(K, 2)`` rows ``(r, phi)``.

    One feature may be given as a ``(3,)`` or ``(2,)`` row; no feature (an empty array) is
    ``(0, 3)``. Ranges must be ``>= 0``.
    """
    z = finite(value, name)
    if z.size == 0:
        return np.zeros((0, 3))
    if z.ndim == 1:
        z = z[None, :]
    if z.ndim != 2 or z.shape[1] not in (2, 3):
        raise ValueError(
            f"{name} must have shape (K, 3) (r, phi, s) or (K, 2) (r, phi), got {z.shape}"
        )
    if _min(z[:, 0]) < 0:
        raise ValueError(f"{name}: ranges must be >= 0")
    return z


def landmark_indices(value, name: str, count: int, n_landmarks: int) -> np.ndarray:
    """Return ``count`` integer landmark rows in ``0 .. n_landmarks - 1`` (shape ``(count,)``).

    Integral floats such as ``2.0`` are accepted; ``0.5``, NaN and out-of-range rows are not.
    """
    arr = np.asarray(value)
    if arr.size == 0 and count == 0:
        return np.zeros(0, dtype=int)
    if arr.ndim == 0:
        arr = arr[None]
    integral = arr.dtype.kind in "iu" or (
        arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr))
    )
    if not integral:
        raise ValueError(f"{name} must hold integer landmark indices, got {_short(value)}")
    if arr.shape != (count,):
        raise ValueError(
            f"{name} must have shape ({count},), one landmark index per feature, got {arr.shape}"
        )
    if _min(arr) < 0 or _max(arr) >= n_landmarks:
        raise ValueError(
            f"{name} must index the map's {n_landmarks} landmarks, got {arr.tolist()}"
        )
    return arr.astype(int)


def sigmas(value, name: str, lengths: tuple[int, ...], *, positive: bool) -> np.ndarray:
    """Return measurement standard deviations :math:`(\\sigma_r, \\sigma_\\phi[, \\sigma_s])`.

    Shape ``(k,)`` with ``k`` in ``lengths``; each ``> 0`` if ``positive`` (a filter divides
    by them), else ``>= 0`` (a density of zero noise is a point mass).
    """
    arr = finite(value, name)
    if arr.ndim != 1 or arr.shape[0] not in lengths:
        need = " or ".join(("(σ_r, σ_φ, σ_s)" if k == 3 else "(σ_r, σ_φ)") for k in lengths)
        raise ValueError(f"{name} must hold the standard deviations {need}, got shape {arr.shape}")
    if _min(arr) <= 0 if positive else _min(arr) < 0:
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"{name} are standard deviations and must be {bound}, got {arr.tolist()}")
    return arr


def step_lengths(value, name: str, n: int) -> np.ndarray:
    """Return ``n`` finite step lengths ``> 0`` (one value for all, or one per step), shape (n,)."""
    dt = finite(value, name)
    if dt.shape not in ((), (n,)):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got shape {dt.shape}")
    if np.any(dt <= 0):
        raise ValueError(f"{name} must be > 0, got {_short(value)}")
    return np.broadcast_to(dt, (n,))


__all__ += [
    "covariance",
    "features",
    "is_positive_semidefinite",
    "landmark_indices",
    "landmark_map",
    "open_probability",
    "sigmas",
    "step_lengths",
    "vector",
]
