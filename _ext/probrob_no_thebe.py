"""Sphinx extension: keep sphinx-thebe (which Jupyter Book 1 always loads) out of the pages.

The book has no live kernel (``launch_buttons.thebe: false``), yet sphinx-thebe's listeners add
to every page a ``const THEBE_JS_URL = "https://unpkg.com/..."`` script (twice: the second
declaration throws "Identifier 'THEBE_JS_URL' has already been declared"), its loader
``sphinx-thebe.js``, its stylesheet and a ``text/x-thebe-config`` block naming a placeholder
Binder repository. This extension disconnects those listeners and drops the stylesheet, so no
page refers to thebe at all (``.ci/browser_check.py`` fails on a page that does).
"""

from __future__ import annotations


def _drop_thebe_css(app) -> None:
    files = app.registry.css_files
    files[:] = [(name, attrs) for name, attrs in files if name != "sphinx-thebe.css"]


def setup(app):
    app.setup_extension("sphinx_thebe")  # loaded first, so that its listeners exist to remove
    for listeners in app.events.listeners.values():
        listeners[:] = [
            lst for lst in listeners if getattr(lst.handler, "__module__", "") != "sphinx_thebe"
        ]
    _drop_thebe_css(app)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
