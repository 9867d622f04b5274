"""Tests of the loaders' download (probrob.datasets with pooch), without the network.

A loopback HTTP server (127.0.0.1, a free port, a thread of this process) serves a temporary
copy of the data folder beside the repository, laid out as it is (``<folder>/<file>``);
``$PROBROB_DATA_URL`` points at it, ``$PROBROB_CACHE`` at an empty folder, and the folder
beside the repository is moved out of sight. So every file the loaders read comes through the
download path, and every request is counted. Nothing here reaches beyond 127.0.0.1.

The last test is a reader's first run: a ``git clone`` of this repository (its committed
HEAD: commit a change before testing it here) with no data beside it, one chapter notebook
executed in a kernel that imports the clone's own ``src``, the data coming from the server.

Needs the real files (``../shared/data`` beside the repository, or ``$PROBROB_DATA``), as
``tests/test_datasets.py``; skipped with the reason when they are absent.
"""

from __future__ import annotations

import dataclasses
import functools
import gc
import hashlib
import http.server
import importlib.util
import json
import logging
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import nbformat
import numpy as np
import pytest

from probrob import datasets
from probrob.datasets import (
    DatasetCorruptError,
    DatasetNotFoundError,
    load_intel_lab,
    load_lnpr_wall,
    load_mrclam,
)

ROOT = Path(__file__).resolve().parents[1]
_DEFAULT_DATA = Path(os.path.normpath(Path(datasets.__file__).resolve().parents[2] / ".."))
_DEFAULT_DATA = _DEFAULT_DATA / "shared" / "data"


def _data_root() -> Path | None:
    """The folder holding the three dataset folders, found as tests/test_datasets.py does."""
    env = os.environ.get("PROBROB_DATA")
    for base in ([Path(env)] if env else []) + [_DEFAULT_DATA]:
        if all((base / ds.folder).is_dir() for ds in datasets._DATASETS):
            return base
    return None


DATA = _data_root()
pytestmark = pytest.mark.skipif(
    DATA is None,
    reason=f"data absent: no dataset folders under $PROBROB_DATA or {_DEFAULT_DATA}",
)

# loader, its dataset, the files it reads
LOADERS = {
    "mrclam": (load_mrclam, datasets._MRCLAM, [f.name for f in datasets._MRCLAM.files]),
    "intel": (load_intel_lab, datasets._INTEL, ["intel-corrected.log.gz"]),
    "lnpr200": (functools.partial(load_lnpr_wall, 200), datasets._LNPR, ["sensor_data_200.txt"]),
    "lnpr600": (functools.partial(load_lnpr_wall, 600), datasets._LNPR, ["sensor_data_600.txt"]),
}


# --------------------------------------------------------------------------- the server


class _Server:
    """A static file server of ``root`` on 127.0.0.1 that records the path of every GET."""

    def __init__(self, root: Path):
        requests = self.requests = []

        class Handler(http.server.SimpleHTTPRequestHandler):
            def __init__(self, *args, **kwargs):
                super().__init__(*args, directory=str(root), **kwargs)

            def do_GET(self):
                requests.append(self.path)
                super().do_GET()

            def log_message(self, format, *args):  # no access log on stderr
                pass

        self.httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}"
        self.thread = threading.Thread(
            target=self.httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True
        )
        self.thread.start()

    def close(self):
        self.httpd.shutdown()
        self.httpd.server_close()
        self.thread.join(timeout=10)


def _copy_data(dst: Path) -> Path:
    """A copy of the dataset files (not SOURCE.md), ``<folder>/<file>`` as in the data folder."""
    for ds in datasets._DATASETS:
        (dst / ds.folder).mkdir(parents=True)
        for f in ds.files:
            shutil.copyfile(DATA / ds.folder / f.name, dst / ds.folder / f.name)
    return dst


def _offline_env(monkeypatch, tmp_path, url: str) -> Path:
    """The loaders' environment of a reader with no data: returns the (empty) cache folder."""
    cache = tmp_path / "cache"
    monkeypatch.delenv("PROBROB_DATA", raising=False)
    monkeypatch.delenv("PROBROB_DOWNLOAD", raising=False)
    monkeypatch.setenv("PROBROB_DATA_URL", url)
    monkeypatch.setenv("PROBROB_CACHE", str(cache))
    monkeypatch.setenv("NO_PROXY", "127.0.0.1,localhost")  # a proxy must not see loopback
    monkeypatch.setenv("no_proxy", "127.0.0.1,localhost")
    monkeypatch.setattr(datasets, "_REPOSITORY", tmp_path / "nowhere" / "repo")
    monkeypatch.setattr(datasets, "_RETRIES", 0)  # a failed download is not tried again
    return cache


@pytest.fixture
def server(tmp_path):
    srv = _Server(_copy_data(tmp_path / "www"))
    srv.root = tmp_path / "www"
    yield srv
    srv.close()
    gc.collect()  # an unclosed connection warns here, in the test that left it


@pytest.fixture
def cache(server, monkeypatch, tmp_path):
    return _offline_env(monkeypatch, tmp_path, server.url)


def _files_under(folder: Path) -> list[str]:
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def _assert_same(a, b):
    """Two loads of one dataset hold equal values (all fields but the folder read from)."""
    assert type(a) is type(b)
    for f in dataclasses.fields(a):
        if f.name in ("folder", "_steps"):
            continue
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, f.name
            np.testing.assert_array_equal(x, y, err_msg=f.name)
        else:
            assert x == y, f.name


def _pooch_logger() -> logging.Logger:
    import pooch

    return pooch.get_logger()


# --------------------------------------------------------------------------- downloading


def test_the_registry_is_the_published_one():
    """pooch's registry: every file under ``<folder>/<name>``, its SOURCE.md sha256, and its
    own byte-identical copy as the address when no mirror is set."""
    for ds in datasets._DATASETS:
        for f in ds.files:
            key = f"{ds.folder}/{f.name}"
            assert datasets._REGISTRY[key] == f"sha256:{f.sha256}"
            assert datasets._URLS[key] == f.url and f.url.startswith("https://")
    assert len(datasets._REGISTRY) == len(datasets._URLS) == 8


@pytest.mark.parametrize("which", list(LOADERS))
def test_each_loader_downloads_checks_and_loads_as_the_local_read(
    which, server, cache, capfd, monkeypatch
):
    load, ds, names = LOADERS[which]
    level = _pooch_logger().level
    got = load()
    out, err = capfd.readouterr()
    assert (out, err) == ("", ""), "a download must print nothing (a notebook cell shows it)"
    assert _pooch_logger().level == level  # pooch's logger is left as it was
    assert Path(got.folder) == cache / ds.folder
    assert sorted(server.requests) == sorted(f"/{ds.folder}/{n}" for n in names)
    assert _files_under(cache) == sorted(f"{ds.folder}/{n}" for n in names)  # no temporaries
    for n in names:
        digest = hashlib.sha256((cache / ds.folder / n).read_bytes()).hexdigest()
        assert digest == ds.file(n).sha256
    _assert_same(got, load(path=DATA / ds.folder))

    # again: the same object, no request
    assert load() is got
    # as in a new session: nothing remembered (no verified file; new modification times, so
    # no parsed result either), the files read from the cache and hash-checked, no request
    monkeypatch.setattr(datasets, "_VERIFIED", {})
    for n in names:
        st = (cache / ds.folder / n).stat()
        os.utime(cache / ds.folder / n, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))
    again = load()
    assert again is not got and Path(again.folder) == cache / ds.folder
    _assert_same(again, got)
    assert len(server.requests) == len(names)


def test_without_a_mirror_each_file_comes_from_its_own_address(server, cache, monkeypatch):
    """No $PROBROB_DATA_URL: each file from its ``_File.url`` (here moved to the loopback
    server under other names, as the published copies have their own paths)."""
    monkeypatch.delenv("PROBROB_DATA_URL")
    elsewhere = server.root / "published" / "x"
    elsewhere.mkdir(parents=True)
    shutil.copyfile(server.root / "lnpr_wall_lidar" / "sensor_data_200.txt", elsewhere / "s200")
    monkeypatch.setitem(
        datasets._URLS, "lnpr_wall_lidar/sensor_data_200.txt", f"{server.url}/published/x/s200"
    )
    assert load_lnpr_wall(200).folder == str(cache / "lnpr_wall_lidar")
    assert server.requests == ["/published/x/s200"]


def test_a_mirror_url_may_end_in_a_slash(server, cache, monkeypatch):
    monkeypatch.setenv("PROBROB_DATA_URL", server.url + "/")
    load_lnpr_wall(200)
    assert server.requests == ["/lnpr_wall_lidar/sensor_data_200.txt"]


def test_only_missing_files_are_downloaded(server, cache):
    """A cache holding some of MRCLAM's files: only the others are requested."""
    (cache / "mrclam_dataset7_robot1").mkdir(parents=True)
    for name in ("Barcodes.dat", "Robot1_Odometry.dat"):
        shutil.copyfile(
            DATA / "mrclam_dataset7_robot1" / name, cache / "mrclam_dataset7_robot1" / name
        )
    load_mrclam()
    assert sorted(server.requests) == [
        "/mrclam_dataset7_robot1/Landmark_Groundtruth.dat",
        "/mrclam_dataset7_robot1/Robot1_Groundtruth.dat",
        "/mrclam_dataset7_robot1/Robot1_Measurement.dat",
    ]


@pytest.mark.parametrize(
    ("folder", "name", "load"),
    [
        ("lnpr_wall_lidar", "sensor_data_600.txt", functools.partial(load_lnpr_wall, 600)),
        ("mrclam_dataset7_robot1", "Robot1_Measurement.dat", load_mrclam),
        ("intel_lab_corrected", "intel-corrected.log.gz", load_intel_lab),
    ],
)
def test_a_corrupt_download_is_refused_and_not_kept(server, cache, folder, name, load):
    served = server.root / folder / name
    data = bytearray(served.read_bytes())
    data[len(data) // 2] ^= 0x01  # one byte changed, same size
    served.write_bytes(bytes(data))
    with pytest.raises(DatasetCorruptError, match=re.escape(name)) as info:
        load()
    url = f"{server.url}/{folder}/{name}"
    assert url in str(info.value) and info.value.url == url
    assert info.value.file == str(cache / folder / name)
    assert hashlib.sha256(bytes(data)).hexdigest() in str(info.value)  # the sha256 it had
    assert "not kept" in str(info.value)
    assert not (cache / folder / name).exists()
    assert name not in " ".join(_files_under(cache))  # no temporary copy either
    assert server.requests.count(f"/{folder}/{name}") == 1  # _RETRIES = 0 here
    # the mirror repaired: the next load downloads it again and succeeds
    shutil.copyfile(DATA / folder / name, served)
    load()
    assert (cache / folder / name).is_file()


def test_a_corrupt_file_in_the_cache_is_downloaded_again(server, cache, monkeypatch):
    folder, name = "lnpr_wall_lidar", "sensor_data_200.txt"
    (cache / folder).mkdir(parents=True)
    broken = bytearray((DATA / folder / name).read_bytes())
    broken[100] = ord("7") if broken[100] != ord("7") else ord("8")
    (cache / folder / name).write_bytes(bytes(broken))
    monkeypatch.setenv("PROBROB_DOWNLOAD", "0")  # switched off: refused, and left alone
    with pytest.raises(DatasetCorruptError, match=re.escape(str(cache / folder / name))):
        load_lnpr_wall(200)
    assert server.requests == [] and (cache / folder / name).read_bytes() == bytes(broken)
    monkeypatch.delenv("PROBROB_DOWNLOAD")
    assert load_lnpr_wall(200).lidar.size == 58988
    assert server.requests == [f"/{folder}/{name}"]
    assert (cache / folder / name).read_bytes() == (DATA / folder / name).read_bytes()


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # nothing listens there once the socket is closed


def test_a_server_that_is_down_says_what_to_download_and_where(monkeypatch, tmp_path, time_limit):
    port = _closed_port()
    cache = _offline_env(monkeypatch, tmp_path, f"http://127.0.0.1:{port}")
    with time_limit(20), pytest.raises(DatasetNotFoundError) as info:
        load_mrclam()
    msg = str(info.value)
    assert isinstance(info.value, FileNotFoundError) and info.value.file == "Barcodes.dat"
    url = f"http://127.0.0.1:{port}/mrclam_dataset7_robot1/Barcodes.dat"
    (line,) = [li for li in msg.splitlines() if li.startswith("Downloading it from")]
    assert line.startswith(f"Downloading it from {url} failed: ConnectionError: ")
    assert "Connection refused" in line
    # what to download, and where to put it
    assert "'Barcodes.dat' not found" in msg
    assert "http://asrl.utias.utoronto.ca/datasets/mrclam/" in msg
    assert f"A byte-identical copy of this file: {datasets._MRCLAM.files[0].url}" in msg
    assert "Put the files in a folder named 'mrclam_dataset7_robot1' under $PROBROB_DATA" in msg
    assert f"or under the download cache {cache}" in msg
    assert info.value.places[-1] == str(cache / "mrclam_dataset7_robot1")
    assert f"{cache / 'mrclam_dataset7_robot1'}  (the download cache, $PROBROB_CACHE;" in msg
    assert _files_under(cache) == []


def test_a_file_the_mirror_lacks(server, cache):
    (server.root / "intel_lab_corrected" / "intel-corrected.log.gz").unlink()
    with pytest.raises(
        DatasetNotFoundError, match=re.escape("'intel-corrected.log.gz' not found")
    ) as info:
        load_intel_lab()
    assert re.search(r"\nDownloading it from \S+ failed: HTTPError: 404 ", str(info.value))
    assert "acschaefer/ple" in str(info.value)


def test_path_never_downloads(server, cache, tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(DatasetNotFoundError, match="Nothing is downloaded when path= is given"):
        load_lnpr_wall(200, path=empty)
    assert server.requests == [] and not cache.exists()


def test_probrob_data_without_the_dataset_still_downloads(server, cache, monkeypatch, tmp_path):
    """$PROBROB_DATA is a place looked in first, not the only one (as documented)."""
    monkeypatch.setenv("PROBROB_DATA", str(tmp_path / "empty"))
    assert load_lnpr_wall(600).folder == str(cache / "lnpr_wall_lidar")
    assert len(server.requests) == 1


def test_data_found_locally_is_not_downloaded(server, cache, monkeypatch):
    monkeypatch.setenv("PROBROB_DATA", str(server.root))
    assert load_intel_lab().folder == str(server.root / "intel_lab_corrected")
    assert server.requests == [] and not cache.exists()


def test_download_switched_off(server, cache, monkeypatch):
    monkeypatch.setenv("PROBROB_DOWNLOAD", "0")
    with pytest.raises(DatasetNotFoundError, match=re.escape("$PROBROB_DOWNLOAD is '0'")):
        load_lnpr_wall(600)
    assert server.requests == []
    monkeypatch.setenv("PROBROB_DOWNLOAD", "1")
    first = load_lnpr_wall(600)
    monkeypatch.setenv("PROBROB_DOWNLOAD", "0")  # the cache is still read
    assert load_lnpr_wall(600) is first and len(server.requests) == 1


@pytest.mark.parametrize(
    ("var", "value", "message"),
    [
        ("PROBROB_DOWNLOAD", "maybe", r"\$PROBROB_DOWNLOAD must be 0 .* or 1"),
        ("PROBROB_DATA_URL", "ftp://example.org/data", r"\$PROBROB_DATA_URL must be an http"),
    ],
)
def test_bad_settings(server, cache, monkeypatch, var, value, message):
    monkeypatch.setenv(var, value)
    with pytest.raises(ValueError, match=message):
        load_lnpr_wall(200)
    assert server.requests == []


def test_the_cache_defaults_to_poochs_user_cache(monkeypatch):
    import pooch

    monkeypatch.delenv("PROBROB_CACHE", raising=False)
    assert datasets._cache_root() == Path(pooch.os_cache("probrob")).expanduser()
    monkeypatch.setenv("PROBROB_CACHE", "~/elsewhere")
    assert datasets._cache_root() == Path.home() / "elsewhere"


# --------------------------------------------------------------------------- a reader's clone

NOTEBOOK = "mrclam_motion_noise.ipynb"  # the quickest chapter that loads a dataset (~12 s)


def _zmq_wakeup():
    spec = importlib.util.spec_from_file_location(
        "_probrob_zmq_wakeup", ROOT / "_ext" / "probrob_zmq_wakeup.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.skipif(
    shutil.which("git") is None or not (ROOT / ".git").exists(),
    reason="needs git and a git checkout to clone",
)
def test_a_fresh_clone_runs_a_chapter_with_downloaded_data(server, monkeypatch, tmp_path):
    """``git clone`` into a folder with nothing beside it, then the MRCLAM chapter executed
    from a clean start as the book build does (12–21 s: the clone, the kernel, the chapter):
    it runs without error, with the clone's own probrob, the data downloaded into an empty
    cache (each file requested once) and nothing on stderr."""
    from jupyter_client.channels import AsyncZMQSocketChannel
    from nbclient import NotebookClient

    start = time.monotonic()
    clone = tmp_path / "reader" / "probrob"
    subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True, timeout=60)
    assert not (clone.parent / "shared").exists()
    cache = tmp_path / "reader-cache"

    # the kernel: this venv's python (as the Makefile's JUPYTER_PATH ensures), importing the
    # clone's src before the editable install of this checkout
    monkeypatch.setenv("JUPYTER_PATH", str(Path(sys.prefix) / "share" / "jupyter"))
    env = {k: v for k, v in os.environ.items() if not k.startswith("PROBROB_")}
    env.pop("MPLBACKEND", None)  # the kernel's own (inline) backend
    env.update(
        PYTHONPATH=str(clone / "src"),
        PYTHONHASHSEED="0",
        PROBROB_DATA_URL=server.url,
        PROBROB_CACHE=str(cache),
        NO_PROXY="127.0.0.1,localhost",
        no_proxy="127.0.0.1,localhost",
    )
    nb = nbformat.read(clone / "notebooks" / NOTEBOOK, as_version=4)
    for cell in nb.cells:  # as the book build starts: nothing executed
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    nb.cells.append(
        nbformat.v4.new_code_cell(
            "import json as _json, probrob as _p\n"
            "from probrob.datasets import load_mrclam as _load\n"
            "print(_json.dumps({'probrob': _p.__file__, 'folder': _load().folder}))"
        )
    )
    # the build's stall fix (tests/test_zmq_wakeup.py), for this test only
    monkeypatch.setattr(AsyncZMQSocketChannel, "get_msg", AsyncZMQSocketChannel.get_msg)
    _zmq_wakeup().install()
    client = NotebookClient(
        nb,
        timeout=120,  # the Makefile's CELL_TIMEOUT
        startup_timeout=60,
        kernel_name="python3",
        resources={"metadata": {"path": str(clone / "notebooks")}},
    )
    client.execute(env=env)  # a cell that raises fails the test, naming the cell

    facts = json.loads(nb.cells[-1].outputs[-1]["text"])
    assert Path(facts["probrob"]).is_relative_to(clone / "src"), facts
    assert facts["folder"] == str(cache / "mrclam_dataset7_robot1")
    names = [f.name for f in datasets._MRCLAM.files]
    assert sorted(server.requests) == sorted(f"/mrclam_dataset7_robot1/{n}" for n in names)
    stderr = [
        (k, o.get("text", ""))
        for k, cell in enumerate(nb.cells)
        if cell.cell_type == "code"
        for o in cell.outputs
        if o.output_type == "stream" and o.name == "stderr"
    ]
    assert stderr == [], "stderr output breaks the book build (-W) and nbval"
    # 12-21 s measured on a loaded 2-core machine; a stalled cell would wait its 120 s
    assert time.monotonic() - start < 90, "a reader's first run took too long"


def test_the_book_lists_each_files_public_copy_and_size():
    """book/datasets.md's table for fetching by hand, and its download sizes, are the
    registry's."""
    text = " ".join((ROOT / "book" / "datasets.md").read_text(encoding="utf-8").split())
    for ds in datasets._DATASETS:
        row = re.search(rf"\| `{ds.folder}` \| ([^|]*) \| <(\S+)>", text)
        assert row, ds.folder
        for f in ds.files:
            assert f"`{f.name}`" in row.group(1)
            assert f.url in (row.group(2), row.group(2) + f.name), f.url
    sizes = {ds.folder: sum(f.size for f in ds.files) for ds in datasets._DATASETS}
    mrclam, intel, lo, hi = re.search(
        r"MRCLAM is ([\d.]+) MB, the Intel log ([\d.]+) MB, each LNPR file ([\d.]+)–([\d.]+) MB",
        text,
    ).groups()
    assert f"{sizes['mrclam_dataset7_robot1'] / 1e6:.1f}" == mrclam
    assert f"{sizes['intel_lab_corrected'] / 1e6:.2f}" == intel
    lnpr = sorted(f.size / 1e6 for f in datasets._LNPR.files)
    assert (f"{lnpr[0]:.1f}", f"{lnpr[1]:.1f}") == (lo, hi)
    readme = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    (total,) = re.search(r"about (\d+) MB for all three", readme).groups()
    assert f"{sum(sizes.values()) / 1e6:.0f}" == total
