"""The build's own settings agree with each other (Makefile, _config.yml)."""

from __future__ import annotations

import re
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
MAKEFILE = (ROOT / "Makefile").read_text(encoding="utf-8")


def make_variable(name: str) -> str:
    m = re.search(rf"^{name}\s*:?=\s*(\S+)\s*$", MAKEFILE, re.M)
    assert m, f"Makefile defines no {name}"
    return m.group(1)


def test_cell_timeout_is_the_same_for_every_runner():
    # a stall fails after the same time in the book, in nbval and in `make execute`
    timeout = int(make_variable("CELL_TIMEOUT"))
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["execute"]["timeout"] == timeout
    assert "--nbval-cell-timeout=$(CELL_TIMEOUT)" in MAKEFILE
    assert "--nbval-kernel-startup-timeout=$(KERNEL_STARTUP_TIMEOUT)" in MAKEFILE
    assert "$(JUPYTER_EXECUTE) --inplace --timeout $(CELL_TIMEOUT)" in MAKEFILE
    assert "--startup_timeout $(KERNEL_STARTUP_TIMEOUT)" in MAKEFILE
    # far below the 600 s of the stall it must catch, far above the slowest real cell (24.7 s)
    assert 60 <= timeout <= 300
    assert 30 <= int(make_variable("KERNEL_STARTUP_TIMEOUT")) <= 120
