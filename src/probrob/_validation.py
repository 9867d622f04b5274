"""Input checks shared by the library: clear ``ValueError`` messages naming the argument."""

from __future__ import annotations

import numpy as np


def as_float_array(value, name: str) -> np.ndarray:
    """Return ``value`` as a float array, or raise ``ValueError`` naming ``name``."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric array_like, got {value!r}") from exc
    return arr


def finite(value, name: str) -> np.ndarray:
    """Return a finite float array; NaN or ±inf raise ``ValueError`` naming ``name``."""
    arr = as_float_array(value, name)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return arr


def variance(value, name: str = "b2") -> np.ndarray:
    """Return a finite, non-negative float array of variances."""
    arr = as_float_array(value, name)
    if np.any(np.isnan(arr)):
        raise ValueError(f"{name} must not be NaN")
    if np.any(arr < 0):
        raise ValueError(f"{name} is a variance and must be >= 0, got min {arr.min()!r}")
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


def alphas(value, name: str, count: int) -> np.ndarray:
    """Return ``count`` finite, non-negative noise parameters as a ``(count,)`` array."""
    arr = finite(value, name)
    if arr.shape != (count,):
        raise ValueError(f"{name} must hold {count} values (α1..α{count}), got shape {arr.shape}")
    if np.any(arr < 0):
        raise ValueError(f"{name} must be non-negative, got {arr.tolist()}")
    return arr


def positive_scalar(value, name: str) -> float:
    """Return a finite, strictly positive float."""
    arr = finite(value, name)
    if arr.ndim != 0 or not arr > 0:
        raise ValueError(f"{name} must be a positive scalar, got {value!r}")
    return float(arr)


def choice(value, name: str, options: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``options``."""
    if value not in options:
        raise ValueError(f"{name} must be one of {options}, got {value!r}")
    return value


def callable_arg(value, name: str):
    """Return ``value`` if it is callable."""
    if not callable(value):
        raise ValueError(f"{name} must be callable, got {value!r}")
    return value


def size_shape(size) -> tuple[int, ...] | None:
    """Normalise a numpy-style ``size`` argument to a shape tuple (or ``None``)."""
    if size is None:
        return None
    shape = (size,) if np.isscalar(size) else tuple(size)
    try:
        shape = tuple(int(n) for n in shape)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"size must be None, an int or a tuple of ints, got {size!r}") from exc
    if any(n < 0 for n in shape):
        raise ValueError(f"size must not be negative, got {size!r}")
    return shape


def output_shape(batch: tuple[int, ...], size) -> tuple[int, ...]:
    """Shape of a sampler's output: ``size`` if given (``batch`` must broadcast to it)."""
    shape = size_shape(size)
    if shape is None:
        return batch
    try:
        full = np.broadcast_shapes(batch, shape)
    except ValueError:
        full = None
    if full != shape:
        raise ValueError(f"size {shape} is not compatible with the input batch shape {batch}")
    return shape


def scalar_or_array(arr: np.ndarray):
    """Return a Python float for a 0-d array, the array otherwise (scalars in, scalars out)."""
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr
