"""probrob.prose: the text an {eval} role shows is the formatted number, without quotes."""

import numpy as np
import pytest

from probrob.prose import Prose, fmt


@pytest.mark.parametrize(
    ("value", "spec", "text"),
    [
        (0.15237, ".3f", "0.152"),
        (np.float64(0.15237), ".3f", "0.152"),
        (np.int64(12345), ",d", "12,345"),
        (0.0278, ".1%", "2.8%"),
        (-1.3, "+.2f", "-1.30"),
    ],
)
def test_fmt_formats_and_repr_has_no_quotes(value, spec, text):
    shown = fmt(value, spec)
    assert isinstance(shown, Prose) and isinstance(shown, str)
    assert str(shown) == text
    assert repr(shown) == text  # what myst-nb and jupyterlab-myst show as text/plain


def test_fmt_rejects_a_spec_the_value_cannot_take():
    with pytest.raises(ValueError):
        fmt(1.5, ",d")
