"""Numbers for the chapters' prose: a value formatted once, shown the same everywhere.

A chapter's markdown cells take every computed number from the code cell that computes it,
with the MyST inline role ``{eval}`name```. The book is built in myst-nb's inline execution
mode, which evaluates the role in the chapter's kernel; JupyterLab with ``jupyterlab-myst``
(``make lab``) evaluates it in the reader's kernel when the cell is rendered. Both show the
``text/plain`` representation of ``name``. :func:`fmt` makes that representation the
formatted number itself (``0.152``, not ``'0.152'`` with the quotes of a ``str``).

Does not hold: the numbers (they are computed in the chapters), nor any check of a claim
(the chapters ``assert`` those where they compute them).
"""

from __future__ import annotations

__all__ = ["Prose", "fmt"]


class Prose(str):
    """A ``str`` whose ``repr`` is the text itself, so an ``{eval}`` role shows no quotes."""

    __slots__ = ()

    def __repr__(self) -> str:
        return str.__str__(self)


def fmt(value, spec: str = "") -> Prose:
    """Return ``format(value, spec)`` as :class:`Prose`, for an ``{eval}`` role in prose.

    Parameters
    ----------
    value : object
        A number (a Python or numpy scalar) or any object with a ``__format__``.
    spec : str
        A format specification, e.g. ``".3f"``, ``".2e"``, ``",d"`` or ``".1%"``.

    Examples
    --------
    >>> fmt(0.15237, ".3f")
    0.152
    >>> fmt(12345, ",d")
    12,345
    """
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
        value = value.item()  # numpy scalars format like Python numbers
    return Prose(format(value, spec))
