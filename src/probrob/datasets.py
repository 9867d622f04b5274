r"""Loaders for the real robot recordings the book uses.

Holds the loaders of the real recordings: files found, checked against their sha256, parsed.
Does not hold the data (never copied into the repository) or fits to it (:mod:`probrob.fitting`).

Three datasets, each in its own folder (never copied into this repository):

- :func:`load_mrclam` — folder ``mrclam_dataset7_robot1``: UTIAS MRCLAM Dataset 7, robot 1:
  velocity commands, range–bearing to barcoded landmarks, Vicon ground truth
  (Probabilistic Robotics, Secs. 5.3, 6.6, 7.4–7.7);
- :func:`load_intel_lab` — folder ``intel_lab_corrected``: the Intel Research Lab CARMEN
  log, 910 scans × 180 beams at SLAM-corrected poses (Secs. 6.3–6.4);
- :func:`load_lnpr_wall` — folder ``lnpr_wall_lidar``: Ueda's single-beam LiDAR (and IR)
  facing a wall at 200 mm and 600 mm, a reading every ~3 s for 2–3 days (Sec. 6.3).

**Where the files are looked for**, in this order:

1. the ``path`` argument, if given — then *only* there, and nothing is downloaded (a typo
   in an explicit path must not silently load another copy). ``path`` may be the dataset's
   folder itself or a data folder holding it (``path/<folder>``);
2. ``$PROBROB_DATA/<folder>``, if the environment variable is set and not empty;
3. ``shared/data/<folder>`` in the folder that holds the repository (the checkout that
   holds this module, ``src/probrob/datasets.py``, editable install);
4. ``<cache>/<folder>``, the download cache: files downloaded before (checked again like any
   other); ``<cache>`` is ``$PROBROB_CACHE`` if set and not empty, else the user's cache
   folder for ``probrob`` (``pooch.os_cache("probrob")``: ``~/.cache/probrob`` on Linux,
   ``~/Library/Caches/probrob`` on macOS, ``%LOCALAPPDATA%\probrob\probrob\Cache`` on
   Windows);
5. a download, with `pooch <https://www.fatiando.org/pooch/>`_, of each file still missing
   into the cache: from the byte-identical public copy each file's ``SOURCE.md`` names, or,
   if ``$PROBROB_DATA_URL`` is set, from ``$PROBROB_DATA_URL/<folder>/<file>`` (so a web
   server of a data folder laid out like the one beside the repository is a mirror). Set
   ``PROBROB_DOWNLOAD=0`` to never download (steps 1–4 still apply).

The first of the folders 1–3 that holds any of the dataset's files is used; only if none
does, the cache (4) and the download (5) supply the files one by one. ``$PROBROB_DATA`` set
does not stop the download: like the folder beside the repository, it is a place looked in
first, not the only one. A missing file raises :class:`DatasetNotFoundError` (a
``FileNotFoundError``) naming the file, every place looked, why it was not downloaded (the
download's error, in one line, if one was tried) and the publisher's download address.
Every file read is checked against the sha256 published in the dataset's ``SOURCE.md``
(streamed hashing; a verified ``(path, size, mtime)`` is remembered for the session), and a
mismatch raises :class:`DatasetCorruptError` (a ``ValueError``); a downloaded file whose
sha256 is wrong is deleted, never kept in the cache (a corrupt file already in the cache is
downloaded again). The loaders print nothing: pooch's log messages are silenced while it
downloads, and this module logs each download at ``INFO`` level (logger
``probrob.datasets``).

**What comes back**: frozen dataclasses of float64 numpy arrays in SI units (m, s, rad).
Parsed results are cached per (folder, file sizes, modification times), so a second load in
a notebook is instant; therefore the arrays are **read-only** (``arr.flags.writeable`` is
False) — take a ``.copy()`` before modifying one in place.
"""

from __future__ import annotations

import contextlib
import functools
import gzip
import hashlib
import logging
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple, NoReturn

import numpy as np

from .kinematics import _interpolate_track

__all__ = [
    "MRCLAM",
    "CarmenLog",
    "DatasetCorruptError",
    "DatasetNotFoundError",
    "IntelLab",
    "LNPRWall",
    "Step",
    "load_intel_lab",
    "load_lnpr_wall",
    "load_mrclam",
    "read_carmen_log",
]

# src/probrob/datasets.py -> the repository root (src layout).
_REPOSITORY = Path(__file__).resolve().parents[2]
ENV_VAR = "PROBROB_DATA"  # a data folder holding the dataset folders
CACHE_ENV_VAR = "PROBROB_CACHE"  # the download cache, instead of pooch.os_cache("probrob")
URL_ENV_VAR = "PROBROB_DATA_URL"  # a mirror: <URL>/<dataset folder>/<file>
DOWNLOAD_ENV_VAR = "PROBROB_DOWNLOAD"  # 0: never download
# A download gives up after 10 s without a connection or 30 s without data, and is tried
# _RETRIES more times (pooch waits 1 s before the first retry, 1 s more before each next).
_TIMEOUT = (10.0, 30.0)
_RETRIES = 1
_LOG = logging.getLogger(__name__)


class DatasetNotFoundError(FileNotFoundError):
    """A dataset file is not in any of the places looked, and was not downloaded.

    Attributes
    ----------
    file : str
        The missing file's name.
    places : list of str
        Every folder looked in, in search order (the download cache last, unless ``path``
        was given).
    url : str
        Where to download the dataset from its publisher.
    """

    def __init__(self, message: str, *, file: str, places: list[str], url: str):
        super().__init__(message)
        self.file = file
        self.places = places
        self.url = url

    def __str__(self) -> str:
        return str(self.args[0])


class DatasetCorruptError(ValueError):
    """A dataset file's sha256 (or size) differs from the one published in ``SOURCE.md``.

    Attributes
    ----------
    file : str
        The full path of the file that failed the check; for a download, the place in the
        download cache it was refused (the file is not kept).
    url : str
        Where to download an intact copy; for a download, the address it came from.
    """

    def __init__(self, message: str, *, file: str, url: str):
        super().__init__(message)
        self.file = file
        self.url = url


# --------------------------------------------------------------------------- registry


@dataclass(frozen=True)
class _File:
    name: str
    size: int
    sha256: str
    url: str  # a byte-identical copy (the one SOURCE.md's sha256 was taken from)


@dataclass(frozen=True)
class _Dataset:
    folder: str
    title: str
    publisher: str  # the publisher's page, for the error message
    files: tuple[_File, ...]

    def file(self, name: str) -> _File:
        return next(f for f in self.files if f.name == name)


_MUSI = (
    "https://raw.githubusercontent.com/ericguerrero/MUSI-lab-session-1/"
    "bdd68804c10fd1016da19913a8036d1d74cc812a/data/MRCLAM_Dataset7/"
)
_MRCLAM = _Dataset(
    folder="mrclam_dataset7_robot1",
    title="UTIAS MRCLAM Dataset 7, robot 1",
    publisher=(
        "http://asrl.utias.utoronto.ca/datasets/mrclam/ (Dataset 7, Robot 1 files; cite "
        "Leung et al., IJRR 30(8), 2011)"
    ),
    files=tuple(
        _File(name, size, sha, _MUSI + name)
        for name, size, sha in [
            (
                "Barcodes.dat",
                384,
                "4b4f4d9e65c452f58a6df2e02f25b5aced4300bd32cfbdb0acd8439692f09683",
            ),
            (
                "Landmark_Groundtruth.dat",
                1084,
                "eb401c2c97f8bcf827dd3c0695b4c8a71c495a217b0aa6f5465fe84bfda71345",
            ),
            (
                "Robot1_Groundtruth.dat",
                3212106,
                "bc03c2f7ff2735a013fd7e7538de3e3b015f216d1074dc5c27747efdf6409371",
            ),
            (
                "Robot1_Measurement.dat",
                126109,
                "83620487d6116c46d1695f7efa7bacf2c9998d700fe291a14cd34c090d082018",
            ),
            (
                "Robot1_Odometry.dat",
                1933958,
                "3f91fa6b20e11fe294b637e638569d8b593972f4ae86c434951638ad595a5e38",
            ),
        ]
    ),
)
_INTEL = _Dataset(
    folder="intel_lab_corrected",
    title="Intel Research Lab corrected CARMEN log",
    publisher=(
        "Radish, http://radish.sourceforge.net/ (the 'intel' log by D. Hähnel); the corrected "
        "log as distributed in https://github.com/acschaefer/ple (data/carmen/)"
    ),
    files=(
        _File(
            "intel-corrected.log.gz",
            448366,
            "71bef16e9926506cf7417995ef35ace09dbd5de067fd042a3aab85188b5480dc",
            "https://raw.githubusercontent.com/acschaefer/ple/"
            "cfcb5a7f12a793b616357381a688cfcc26eed347/data/carmen/intel-corrected.log.gz",
        ),
    ),
)
_LNPR_URL = (
    "https://raw.githubusercontent.com/ryuichiueda/LNPR_BOOK_CODES/"
    "73f4549ae45712aa83c9b403c90e67fe653fa04b/sensor_data/"
)
_LNPR = _Dataset(
    folder="lnpr_wall_lidar",
    title="LNPR wall LiDAR (Ueda)",
    publisher=(
        "https://github.com/ryuichiueda/LNPR_BOOK_CODES (sensor_data/; MIT, © 2019 Ryuichi Ueda)"
    ),
    files=(
        _File(
            "sensor_data_200.txt",
            1415712,
            "765777bcee3fe9506212e2b1dbbcbf952881ae4cef049366095898d7f55ee53f",
            _LNPR_URL + "sensor_data_200.txt",
        ),
        _File(
            "sensor_data_600.txt",
            1891987,
            "835a5676db88157e590107d59dd5dc2dc0254b79e26213b1c2ec61a171b9f790",
            _LNPR_URL + "sensor_data_600.txt",
        ),
    ),
)


# The download registry, as pooch takes it: "<folder>/<file>" -> "sha256:<hex>", and each
# file's own address (used unless $PROBROB_DATA_URL names a mirror).
_DATASETS = (_MRCLAM, _INTEL, _LNPR)
_REGISTRY = {f"{ds.folder}/{f.name}": f"sha256:{f.sha256}" for ds in _DATASETS for f in ds.files}
_URLS = {f"{ds.folder}/{f.name}": f.url for ds in _DATASETS for f in ds.files}


# --------------------------------------------------------------------------- finding files


def _path_argument(path) -> Path:
    try:
        p = Path(os.fspath(path)).expanduser()
    except TypeError as exc:
        raise ValueError(
            f"path must be a folder (str or os.PathLike), got {type(path).__name__} {path!r}"
        ) from exc
    if p.exists() and not p.is_dir():
        raise ValueError(f"path must be a folder, got the file {str(p)!r}")
    return p


def _places(ds: _Dataset, path) -> list[tuple[Path, str]]:
    """The folders to look in, in search order, each with a note on where it came from."""
    if path is not None:
        p = _path_argument(path)
        return [(p, "the path argument"), (p / ds.folder, "the path argument's sub-folder")]
    places = []
    env = os.environ.get(ENV_VAR, "")
    if env:
        places.append((Path(env).expanduser() / ds.folder, f"${ENV_VAR}/{ds.folder}"))
    places.append(
        (
            Path(os.path.normpath(_REPOSITORY / ".." / "shared" / "data" / ds.folder)),
            f"shared/data/{ds.folder} beside the repository",
        )
    )
    return places


def _cache_root() -> Path:
    """The download cache: ``$PROBROB_CACHE``, else ``pooch.os_cache("probrob")``."""
    env = os.environ.get(CACHE_ENV_VAR, "")
    if env:
        return Path(env).expanduser()
    import pooch  # only when the files are not beside the repository: ~0.1 s to import

    return Path(pooch.os_cache("probrob")).expanduser()


def _download_allowed() -> bool:
    value = os.environ.get(DOWNLOAD_ENV_VAR, "")
    if value.strip().lower() in ("", "1", "true", "yes", "on"):
        return True
    if value.strip().lower() in ("0", "false", "no", "off"):
        return False
    raise ValueError(
        f"${DOWNLOAD_ENV_VAR} must be 0 (never download a missing dataset file) or 1 (download "
        f"it into the cache, the default when unset), got {value!r}"
    )


def _base_url() -> str | None:
    """``$PROBROB_DATA_URL`` without its trailing slashes, or None when unset or empty."""
    url = os.environ.get(URL_ENV_VAR, "").strip()
    if not url:
        return None
    if not url.startswith(("http://", "https://")):
        raise ValueError(
            f"${URL_ENV_VAR} must be an http:// or https:// address under which "
            f"<dataset folder>/<file> is served, got {url!r}"
        )
    return url.rstrip("/")


def _locate(ds: _Dataset, names: tuple[str, ...], path) -> dict[str, Path]:
    """Return ``{name: file}`` for ``names``: all from the first folder holding any of them,
    else each from the download cache (downloading it there if missing)."""
    places = _places(ds, path)
    for folder, _ in places:
        if folder.is_dir() and any((folder / n).is_file() for n in names):
            missing = [n for n in names if not (folder / n).is_file()]
            if missing:
                _not_found(ds, missing[0], places, chosen=folder)
            return {n: folder / n for n in names}
    if path is not None:
        _not_found(
            ds,
            names[0],
            places,
            why="Nothing is downloaded when path= is given; without it, a missing file is "
            "downloaded into the download cache.",
        )
    note = "the download cache" + (f", ${CACHE_ENV_VAR}" if os.environ.get(CACHE_ENV_VAR) else "")
    root = _cache_root()
    places.append((root / ds.folder, note))
    return {n: _cached_or_downloaded(ds, n, root, places) for n in names}


def _cached_or_downloaded(ds: _Dataset, name: str, root: Path, places) -> Path:
    """The file ``name`` in the cache ``root``, checked; downloaded first if it is not there."""
    file = root / ds.folder / name
    allowed = _download_allowed()
    if file.is_file():
        try:
            _verify(ds, file)
            return file
        except DatasetCorruptError:
            if not allowed:
                raise
            _LOG.info("deleting the corrupt %s from the download cache", file)
            file.unlink()  # the cache's own copy: replaced by a new download
    if not allowed:
        _not_found(
            ds,
            name,
            places,
            why=f"Not downloaded: ${DOWNLOAD_ENV_VAR} is {os.environ[DOWNLOAD_ENV_VAR]!r}.",
            cache=root,
        )
    base = _base_url()
    key = f"{ds.folder}/{name}"
    url = f"{base}/{key}" if base else _URLS[key]
    error = _download(key, url, root, base)
    if error is not None:
        _not_found(ds, name, places, why=f"Downloading it from {url} failed: {error}", cache=root)
    _verify(ds, file)  # pooch checked the sha256; this remembers the file as verified
    return file


@contextlib.contextmanager
def _pooch_silenced(pooch):
    """Pooch logs every download to stderr (its own handler): a notebook cell would show it."""
    logger = pooch.get_logger()
    level = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        logger.setLevel(level)


def _download(key: str, url: str, root: Path, base: str | None) -> str | None:
    """Download the registry file ``key`` from ``url`` into ``root/key`` with pooch.

    Returns None once the file is in place with its published sha256, or, in one line, the
    error that stopped the download. A file with another sha256 is deleted by pooch (it downloads into a
    temporary file beside the target and moves it there only once the hash matches) and
    raises :class:`DatasetCorruptError`.
    """
    import pooch
    import requests

    fetcher = pooch.create(
        path=root,
        base_url=base or "",
        registry=_REGISTRY,
        urls=None if base else _URLS,
        retry_if_failed=_RETRIES,
    )
    downloader = pooch.HTTPDownloader(progressbar=False, chunk_size=65536, timeout=_TIMEOUT)
    _LOG.info("downloading %s from %s into %s", key, url, root)
    try:
        with _pooch_silenced(pooch):
            fetcher.fetch(key, downloader=downloader)
    except ValueError as exc:
        if "does not match the known hash" not in str(exc):
            raise
        folder, name = key.split("/")
        ds = next(d for d in _DATASETS if d.folder == folder)
        got = re.search(r"but got (\w+)", str(exc))
        raise DatasetCorruptError(
            f"{ds.title}: {name} downloaded from {url} is corrupt or a different version "
            f"(sha256 {got.group(1) if got else '?'} instead of {ds.file(name).sha256}, as "
            f"published in SOURCE.md); it was not kept in {root / folder}. The publisher: "
            f"{ds.publisher}.",
            file=str(root / key),
            url=url,
        ) from None
    except (requests.exceptions.RequestException, OSError) as exc:
        response = getattr(exc, "response", None)
        if response is not None:  # an HTTP error: pooch leaves its connection open
            response.close()
        return " ".join(f"{type(exc).__name__}: {exc}".split())
    return None


def _not_found(
    ds: _Dataset,
    name: str,
    places,
    chosen: Path | None = None,
    why: str = "",
    cache: Path | None = None,
) -> NoReturn:
    looked = []
    for folder, note in places:
        state = "exists" if folder.is_dir() else "does not exist"
        if folder == chosen:
            state = f"exists but has no {name}"
        looked.append(f"  - {folder}  ({note}; {state})")
    if not os.environ.get(ENV_VAR):
        looked.append(f"  (${ENV_VAR} is not set)")
    spec = ds.file(name)
    message = (
        f"{ds.title}: file {name!r} not found.\nLooked in:\n"
        + "\n".join(looked)
        + (f"\n{why}" if why else "")
        + f"\nDownload the dataset from its publisher: {ds.publisher}\n"
        f"A byte-identical copy of this file: {spec.url}\n"
        f"Put the files in a folder named {ds.folder!r} under ${ENV_VAR} (or under "
        f"shared/data beside the repository"
        + (f", or under the download cache {cache}" if cache is not None else "")
        + "), or pass path=<that folder>."
    )
    raise DatasetNotFoundError(
        message, file=name, places=[str(f) for f, _ in places], url=ds.publisher
    )


# Verified files: (resolved path, size, mtime_ns) -> sha256.
_VERIFIED: dict[tuple[str, int, int], str] = {}


def _stamp(file: Path) -> tuple[str, int, int]:
    st = file.stat()
    return (str(file.resolve()), st.st_size, st.st_mtime_ns)


def _verify(ds: _Dataset, file: Path) -> None:
    """Check ``file`` against its published sha256 (streamed), once per (path, size, mtime)."""
    spec = ds.file(file.name)
    key = _stamp(file)
    if _VERIFIED.get(key) == spec.sha256:
        return
    if key[1] != spec.size:
        got = f"{key[1]} bytes instead of {spec.size}"
    else:
        with open(file, "rb") as fh:
            digest = hashlib.file_digest(fh, "sha256").hexdigest()
        if digest == spec.sha256:
            _VERIFIED[key] = digest
            return
        got = f"sha256 {digest} instead of {spec.sha256}"
    raise DatasetCorruptError(
        f"{ds.title}: {file} is corrupt or a different version ({got}, as published in "
        f"SOURCE.md). Download it again: {spec.url} (publisher: {ds.publisher}).",
        file=str(file),
        url=spec.url,
    )


def _stamps(files) -> tuple:
    return tuple(_stamp(f) for f in files)


def _readonly(*arrays):
    for a in arrays:
        a.setflags(write=False)


def _summary(obj, names) -> str:
    parts = []
    for n in names:
        v = getattr(obj, n)
        parts.append(f"{n}={v.shape}" if isinstance(v, np.ndarray) else f"{n}={v!r}")
    return f"{type(obj).__name__}({', '.join(parts)})"


# --------------------------------------------------------------------------- MRCLAM


class Step(NamedTuple):
    r"""One filter step of :meth:`MRCLAM.stream`: a control and the measurements that follow it.

    A named tuple (cheap to build 58,597 of them; immutable; its arrays are read-only).

    Attributes
    ----------
    t : float
        End of the odometry interval, :math:`t_{i+1}` [s, Unix epoch]: the time of the
        belief after this step.
    dt : float
        Interval length :math:`t_{i+1} - t_i` [s] (> 0; 0.01 s typically, at most 1.0 s).
    u : ndarray, shape (2,)
        The velocity command :math:`(v, \omega)` [m/s, rad/s] logged at :math:`t_i`,
        held over the interval.
    z : ndarray, shape (k, 3)
        Landmark measurements :math:`(r, \phi, s)` [m, rad, barcode] with time in
        :math:`(t_i, t_{i+1}]`, in file order; ``k`` may be 0.
    c : ndarray of int, shape (k,)
        Their correspondences: row indices into :attr:`MRCLAM.landmarks`.
    z_t : ndarray, shape (k,)
        Their time stamps [s].
    """

    t: float
    dt: float
    u: np.ndarray
    z: np.ndarray
    c: np.ndarray
    z_t: np.ndarray

    def __repr__(self) -> str:
        return (
            f"Step(t={self.t!r}, dt={self.dt:.3f}, u={self.u.tolist()}, "
            f"z={self.z.shape}, c={self.c.tolist()})"
        )


@dataclass(frozen=True, eq=False)
class MRCLAM:
    r"""UTIAS MRCLAM Dataset 7, robot 1, as returned by :func:`load_mrclam`.

    Times are Unix epoch seconds as in the files (float64 keeps them to better than
    1 µs). All arrays are read-only.

    Attributes
    ----------
    odometry_t : ndarray, shape (N,)
        Times of the velocity commands [s]; strictly increasing. N = 58,598.
    odometry : ndarray, shape (N, 2)
        Velocity commands :math:`(v, \omega)` [m/s, rad/s] (the dataset's "odometry" is
        the commanded velocity, not wheel encoders).
    ground_truth_t : ndarray, shape (M,)
        Vicon time stamps [s]; strictly increasing. M = 58,389; starts 6 s before the
        first command.
    ground_truth : ndarray, shape (M, 3)
        Vicon poses :math:`(x, y, \theta)` [m, m, rad], θ in :math:`[-\pi, \pi]`.
    measurement_t : ndarray, shape (K,)
        Times of the landmark measurements [s]; non-decreasing (several per image share a
        time). K = 2,578.
    measurements : ndarray, shape (K, 3)
        :math:`(r, \phi, s)` [m, rad, –]: range, bearing (counter-clockwise from the
        heading) and the signature ``s`` = the landmark's **barcode number**, as read by
        the camera (Probabilistic Robotics, Sec. 6.6: :math:`z = (r, \phi, s)`).
    correspondences : ndarray of int, shape (K,)
        The landmark each measurement is of: row index into :attr:`landmarks`
        (from the barcode through ``Barcodes.dat`` of Dataset 7).
    sighting_t : ndarray, shape (R,)
        Times of the sightings of other robots [s]. R = 650.
    sightings : ndarray, shape (R, 2)
        :math:`(r, \phi)` [m, rad] to the sighted robot.
    sighted_robot : ndarray of int, shape (R,)
        The sighted robot's number, 2…5 (subject number; robot 1 never sees itself).
    landmarks : ndarray, shape (L, 3)
        The map: :math:`(x, y, s)` [m, m, –] from ``Landmark_Groundtruth.dat``, one row per
        landmark in order of subject number 6…20 (L = 15); ``s`` is the landmark's barcode,
        the same number as in :attr:`measurements`.
    landmark_std : ndarray, shape (L, 2)
        Standard deviations of the surveyed x, y [m] (all ≤ 0.65 mm).
    landmark_subject : ndarray of int, shape (L,)
        The dataset's subject number of each landmark row (6…20).
    barcodes : ndarray of int, shape (20, 2)
        ``Barcodes.dat``: (subject, barcode); subjects 1–5 are robots, 6–20 landmarks.
    folder : str
        The folder the files were read from.
    """

    odometry_t: np.ndarray
    odometry: np.ndarray
    ground_truth_t: np.ndarray
    ground_truth: np.ndarray
    measurement_t: np.ndarray
    measurements: np.ndarray
    correspondences: np.ndarray
    sighting_t: np.ndarray
    sightings: np.ndarray
    sighted_robot: np.ndarray
    landmarks: np.ndarray
    landmark_std: np.ndarray
    landmark_subject: np.ndarray
    barcodes: np.ndarray
    folder: str
    _steps: tuple | None = field(default=None, init=False, repr=False)

    def __repr__(self) -> str:
        return _summary(
            self,
            [
                "odometry",
                "ground_truth",
                "measurements",
                "sightings",
                "landmarks",
                "folder",
            ],
        )

    def stream(self) -> list[Step]:
        r"""The recording as filter input: one :class:`Step` per odometry interval.

        The commands are logged at times :math:`t_0 < t_1 < \dots < t_{N-1}`; each is taken
        to hold until the next one. Step ``i`` (``i = 0 … N-2``, so ``N - 1`` = 58,597 steps)
        is the interval :math:`(t_i, t_{i+1}]`:

        - ``u = odometry[i]``, the command logged at :math:`t_i`;
        - ``dt = t_{i+1} - t_i``; ``t = t_{i+1}``;
        - ``z``, ``c``, ``z_t``: every **landmark** measurement with time in
          :math:`(t_i, t_{i+1}]`, in file order. A filter predicts with ``(u, dt)`` to
          ``t`` and then corrects with ``z`` (Probabilistic Robotics, Tables 7.2–7.4); a
          measurement's time is thus rounded up to the end of its interval, by less than
          ``dt`` (0.01 s typically).

        Measurements at or before :math:`t_0` join step 0; those after :math:`t_{N-1}`
        (no command covers them) are left out. Dataset 7 robot 1 has none of either (its
        first measurement is 0.93 s after the first command, its last 0.06 s before the
        last), so every one of the K = 2,578 landmark measurements appears exactly once.
        Robot sightings are not in the stream (see :attr:`sightings`).

        Start the filter at :math:`t_0` = ``odometry_t[0]``, e.g. from
        ``ground_truth_at(odometry_t[0])``.

        Returns
        -------
        steps : list of Step
            ``len(steps) == N - 1``; ``steps[i].t == odometry_t[i + 1]``.
        """
        if self._steps is None:
            object.__setattr__(self, "_steps", tuple(self._make_steps()))
        return list(self._steps)

    def _make_steps(self) -> list[Step]:
        t = self.odometry_t
        n = t.size - 1
        # side="left": t_{j-1} < tm <= t_j  ->  interval j - 1; tm <= t_0 -> -1 -> step 0.
        step = np.maximum(np.searchsorted(t, self.measurement_t, side="left") - 1, 0)
        keep = step < n
        order = np.argsort(step[keep], kind="stable")
        z = self.measurements[keep][order]
        c = self.correspondences[keep][order]
        zt = self.measurement_t[keep][order]
        _readonly(z, c, zt)
        counts = np.bincount(step[keep], minlength=n)
        ends = np.cumsum(counts).tolist()
        starts = [0, *ends[:-1]]
        # Most intervals hold no measurement: they share one empty (read-only) array each.
        empty_z, empty_c, empty_t = z[:0], c[:0], zt[:0]
        t_end, dts, u = t[1:].tolist(), np.diff(t).tolist(), list(self.odometry[:n])
        steps = [Step(t_end[i], dts[i], u[i], empty_z, empty_c, empty_t) for i in range(n)]
        for i in np.flatnonzero(counts).tolist():
            a, b = starts[i], ends[i]
            steps[i] = Step(t_end[i], dts[i], u[i], z[a:b], c[a:b], zt[a:b])
        return steps

    def ground_truth_at(self, t) -> np.ndarray:
        r"""The Vicon pose interpolated at times ``t``.

        x and y are interpolated linearly; θ along the shorter arc (linearly in the
        unwrapped heading), then wrapped to :math:`[-\pi, \pi)`.

        Parameters
        ----------
        t : array_like, shape (...)
            Times [s, Unix epoch] within ``[ground_truth_t[0], ground_truth_t[-1]]``.

        Returns
        -------
        pose : ndarray, shape (..., 3)
        """
        from ._validation import finite

        tq = finite(t, "t")
        lo, hi = self.ground_truth_t[0], self.ground_truth_t[-1]
        if tq.size and (tq.min() < lo or tq.max() > hi):
            raise ValueError(
                f"t must lie within the ground truth's span [{lo:.3f}, {hi:.3f}] s, got "
                f"values in [{tq.min():.3f}, {tq.max():.3f}]"
            )
        return _interpolate_track(self.ground_truth_t, self.ground_truth, tq)


def _loadtxt(ds: _Dataset, file: Path, columns: int) -> np.ndarray:
    """Read a whitespace-separated table (``#`` comments) with ``columns`` columns."""
    a = np.loadtxt(file, dtype=float, comments="#", ndmin=2)
    if a.shape[1] != columns:  # cannot happen once the sha256 matched; kept for safety
        raise DatasetCorruptError(
            f"{file}: expected {columns} columns, got {a.shape[1]}",
            file=str(file),
            url=ds.file(file.name).url,
        )
    return a


@functools.lru_cache(maxsize=4)
def _mrclam_cached(files: tuple[tuple[str, Path], ...], stamps: tuple) -> MRCLAM:
    del stamps  # part of the cache key only: a changed file is read again
    f = dict(files)
    for file in f.values():
        _verify(_MRCLAM, file)
    barcodes = _loadtxt(_MRCLAM, f["Barcodes.dat"], 2).astype(int)
    lm = _loadtxt(_MRCLAM, f["Landmark_Groundtruth.dat"], 5)
    gt = _loadtxt(_MRCLAM, f["Robot1_Groundtruth.dat"], 4)
    meas = _loadtxt(_MRCLAM, f["Robot1_Measurement.dat"], 4)
    odo = _loadtxt(_MRCLAM, f["Robot1_Odometry.dat"], 3)

    lm = lm[np.argsort(lm[:, 0], kind="stable")]
    lm_subject = lm[:, 0].astype(int)
    subject_of_barcode = np.full(barcodes[:, 1].max() + 1, -1)
    subject_of_barcode[barcodes[:, 1]] = barcodes[:, 0]
    row_of_subject = np.full(barcodes[:, 0].max() + 1, -1)
    row_of_subject[lm_subject] = np.arange(lm_subject.size)
    barcode_of_subject = np.zeros(barcodes[:, 0].max() + 1)
    barcode_of_subject[barcodes[:, 0]] = barcodes[:, 1]

    code = meas[:, 1].astype(int)
    subject = subject_of_barcode[code]
    is_landmark = row_of_subject[subject] >= 0
    is_robot = (subject >= 1) & (subject <= 5)

    m_lm = meas[is_landmark]
    m_rb = meas[is_robot]
    out = dict(
        odometry_t=np.ascontiguousarray(odo[:, 0]),
        odometry=np.ascontiguousarray(odo[:, 1:3]),
        ground_truth_t=np.ascontiguousarray(gt[:, 0]),
        ground_truth=np.ascontiguousarray(gt[:, 1:4]),
        measurement_t=np.ascontiguousarray(m_lm[:, 0]),
        measurements=np.ascontiguousarray(m_lm[:, [2, 3, 1]]),
        correspondences=row_of_subject[subject[is_landmark]],
        sighting_t=np.ascontiguousarray(m_rb[:, 0]),
        sightings=np.ascontiguousarray(m_rb[:, 2:4]),
        sighted_robot=subject[is_robot],
        landmarks=np.column_stack([lm[:, 1:3], barcode_of_subject[lm_subject]]),
        landmark_std=np.ascontiguousarray(lm[:, 3:5]),
        landmark_subject=lm_subject,
        barcodes=barcodes,
    )
    _readonly(*out.values())
    return MRCLAM(**out, folder=str(f["Robot1_Odometry.dat"].parent))


def load_mrclam(path=None) -> MRCLAM:
    r"""Load UTIAS MRCLAM Dataset 7, robot 1 (folder ``mrclam_dataset7_robot1``).

    Five iRobot Create robots in a 15 m × 8 m hall (UTIAS, July 2009); this is robot 1's
    complete 15-minute record: velocity commands (~66 Hz), a monocular camera's range and
    bearing to 15 barcoded landmark cylinders and to the other robots, and Vicon ground
    truth (~65 Hz). Cite K. Y. K. Leung, Y. Halpern, T. D. Barfoot, H. H. T. Liu, "The UTIAS
    Multi-Robot Cooperative Localization and Mapping Dataset", IJRR 30(8):969–974, 2011.

    The measurement file stores barcode numbers; they are mapped through ``Barcodes.dat``
    of Dataset 7 (subjects 1–5 robots, 6–20 landmarks): landmark sightings go to
    :attr:`MRCLAM.measurements` with their landmark row in
    :attr:`MRCLAM.correspondences`, sightings of robots to :attr:`MRCLAM.sightings`.
    :meth:`MRCLAM.stream` merges commands and landmark measurements in time order for a
    filter (Probabilistic Robotics, Tables 7.2–7.4).

    Parameters
    ----------
    path : str or os.PathLike, optional
        The dataset folder, or a folder holding it; then nothing is downloaded. Default:
        ``$PROBROB_DATA``, then ``shared/data`` beside the repository, then the download
        cache, downloading a missing file into it (see the module docstring).

    Returns
    -------
    MRCLAM
        Read-only arrays; the same object is returned while the files are unchanged.

    Raises
    ------
    DatasetNotFoundError
        A file is missing and was not downloaded (the message lists every place looked, why
        the download was not made or failed, and the download address).
    DatasetCorruptError
        A file's sha256 differs from the published one (a downloaded one is not kept).
    ValueError
        ``path`` is not a folder, or ``$PROBROB_DOWNLOAD`` or ``$PROBROB_DATA_URL`` is not
        of its form (0 or 1; an http(s) address).
    """
    names = tuple(f.name for f in _MRCLAM.files)
    files = _locate(_MRCLAM, names, path)
    return _mrclam_cached(tuple(files.items()), _stamps(files.values()))


# --------------------------------------------------------------------------- Intel lab


def _carmen_beam_angles(n: int) -> np.ndarray:
    """CARMEN's convention for a FLASER line of ``n`` beams: a 180° scanner from −90°, counter-
    clockwise, at 180°/n for an even ``n`` (180 → 1°, 360 → 0.5°; the last beam at +89°) and
    180°/(n − 1) for an odd one (181 → 1°, 361 → 0.5°; the last beam at +90°)."""
    return -0.5 * np.pi + np.arange(n) * (np.pi / (n - n % 2))


class _CarmenError(ValueError):
    """A malformed CARMEN line (its number and what was expected), for the two readers."""


def _numbers(fields: list[str], what: str, lineno: int) -> list[float]:
    try:
        values = [float(f) for f in fields]
    except ValueError:
        raise _CarmenError(
            f"line {lineno}: {what} must be numbers, got {' '.join(fields)!r}"
        ) from None
    if not all(np.isfinite(values)):
        raise _CarmenError(f"line {lineno}: {what} must be finite, got {' '.join(fields)!r}")
    return values


_CARMEN_NUMERIC_PARAMS = ("robot_frontlaser_offset",)


def _parse_carmen(lines) -> dict:
    """Parse a CARMEN log's FLASER, ODOM, NEFF and PARAM lines (other messages are skipped).

    Returns the scans' time stamps, poses, odometry poses and ranges, the odometry pair of
    every step between consecutive scans, the NEFF values and the PARAM dictionary; raises
    :class:`_CarmenError` naming the line of the first malformed message.
    """
    t, poses, odom, ranges, neff, last_odom = [], [], [], [], [], []
    params: dict[str, str] = {}
    n_beams = None
    for lineno, line in enumerate(lines, start=1):
        f = line.split()
        if not f or f[0].startswith("#"):
            continue
        tag = f[0]
        if tag == "FLASER":
            # FLASER n r_0 … r_{n-1} x y θ odom_x odom_y odom_θ timestamp hostname logger_ts
            if len(f) < 2 or not f[1].isdigit() or int(f[1]) < 1:
                raise _CarmenError(
                    f"line {lineno}: FLASER must be followed by its number of beams, got "
                    f"{' '.join(f[:2])!r}"
                )
            n = int(f[1])
            if n < 2:
                raise _CarmenError(
                    f"line {lineno}: FLASER has 1 beam; CARMEN spreads a FLASER scan's beams "
                    "over 180° from -90°, which takes at least 2 (read a one-beam sensor "
                    "otherwise)"
                )
            if len(f) != n + 11:
                raise _CarmenError(
                    f"line {lineno}: FLASER with {n} beams needs {n + 11} fields (FLASER n, "
                    f"{n} ranges, x y θ, odom_x odom_y odom_θ, timestamp hostname logger "
                    f"timestamp), got {len(f)}"
                )
            if n_beams is not None and n != n_beams:
                raise _CarmenError(
                    f"line {lineno}: FLASER has {n} beams where earlier scans have {n_beams}"
                )
            n_beams = n
            r = _numbers(f[2 : 2 + n], "FLASER ranges", lineno)
            if min(r) < 0:
                raise _CarmenError(f"line {lineno}: FLASER ranges must be >= 0")
            v = _numbers(
                f[2 + n : 8 + n] + [f[8 + n]],
                "FLASER x y θ odom_x odom_y odom_θ timestamp",
                lineno,
            )
            ranges.append(r)
            poses.append(v[0:3])
            odom.append(v[3:6])
            t.append(v[6])
            last_odom.append(None)
        elif tag == "ODOM":
            # ODOM x y θ tv rv accel timestamp hostname logger_timestamp
            if len(f) < 7:
                raise _CarmenError(
                    f"line {lineno}: ODOM needs at least x y θ, a timestamp, a hostname and "
                    f"a logger timestamp, got {len(f) - 1} fields"
                )
            v = _numbers(f[1:4], "ODOM x y θ", lineno)
            if last_odom:
                last_odom[-1] = v
        elif tag == "NEFF":
            if len(f) != 2:
                raise _CarmenError(f"line {lineno}: NEFF needs one value, got {len(f) - 1}")
            neff.append(_numbers(f[1:2], "NEFF", lineno)[0])
        elif tag == "PARAM":
            if len(f) < 3:
                raise _CarmenError(f"line {lineno}: PARAM needs a name and a value")
            if f[1] in _CARMEN_NUMERIC_PARAMS:  # the ones read: a finite number of metres
                _numbers(f[2:3], f"PARAM {f[1]}", lineno)
            params[f[1]] = f[2]
    if not poses:
        raise _CarmenError(
            "the log has no FLASER line (no laser scan; ROBOTLASER1 and RAWLASER messages "
            "are not read)"
        )
    odom_arr = np.array(odom, dtype=float)
    # The odometry of step k: from the odometry pose of scan k to the last ODOM pose logged
    # before scan k + 1 (or, with no ODOM line in between, the odometry pose of scan k + 1).
    ends = np.array(
        [odom[k + 1] if last_odom[k] is None else last_odom[k] for k in range(len(odom) - 1)],
        dtype=float,
    ).reshape(-1, 3)
    return dict(
        t=np.array(t, dtype=float),
        poses=np.array(poses, dtype=float),
        ranges=np.array(ranges, dtype=float),
        odometry=np.stack([odom_arr[:-1], ends], axis=1),
        beam_angles=_carmen_beam_angles(n_beams),
        neff=np.array(neff, dtype=float),
        params=params,
    )


@dataclass(frozen=True, eq=False)
class CarmenLog:
    r"""A CARMEN laser log (FLASER scans with odometry), as returned by :func:`read_carmen_log`.

    All arrays are read-only.

    Attributes
    ----------
    t : ndarray, shape (S,)
        Scan time stamps [s], as logged.
    poses : ndarray, shape (S, 3)
        The pose :math:`(x, y, \theta)` [m, m, rad] written with each scan (raw odometry in a
        raw log; a SLAM-corrected pose in a "corrected" log), θ as in the file.
    ranges : ndarray, shape (S, B)
        Measured ranges [m]. A reading equal to :attr:`max_range` means no return.
    beam_angles : ndarray, shape (B,)
        Beam directions relative to the heading [rad], CARMEN's FLASER convention (a 180°
        scanner from −90°, counter-clockwise; 1° apart for 180 or 181 beams).
    odometry : ndarray, shape (S − 1, 2, 3)
        For each step between consecutive scans, an odometry pair
        :math:`(\bar x_{k}, \bar x_{k+1})`, the ``u`` of Table 5.6: from the odometry pose
        logged with scan k to the last ``ODOM`` pose logged before scan k + 1 (the odometry
        pose of scan k + 1 when no ``ODOM`` line lies between them).
    max_range : float
        The no-return code [m].
    laser_offset : float
        Forward offset of the laser from the robot origin [m] (``PARAM
        robot_frontlaser_offset``; 0 when absent).
    folder : str
        The folder the log was read from.
    """

    t: np.ndarray
    poses: np.ndarray
    ranges: np.ndarray
    beam_angles: np.ndarray
    odometry: np.ndarray
    max_range: float
    laser_offset: float
    folder: str

    def __repr__(self) -> str:
        return _summary(
            self, ["t", "poses", "ranges", "beam_angles", "odometry", "max_range", "folder"]
        )

    @property
    def no_return(self) -> np.ndarray:
        """Boolean mask, shape (S, B): the readings equal to :attr:`max_range`."""
        return self.ranges >= self.max_range


@dataclass(frozen=True, eq=False)
class IntelLab(CarmenLog):
    r"""The Intel Research Lab corrected CARMEN log, as returned by :func:`load_intel_lab`.

    All arrays are read-only. The fields of :class:`CarmenLog`, for this log:

    Attributes
    ----------
    t : ndarray, shape (S,)
        Scan time stamps [s] since the start of the log (not epoch), S = 910. **Not
        monotonic**: as recorded, there are 4 small backward steps (at most 0.86 s).
    poses : ndarray, shape (S, 3)
        The corrected (SLAM, most likely GMapping) pose :math:`(x, y, \theta)` [m, m, rad]
        of each scan, as in the file, θ **not wrapped** (it reaches 3.25 rad). The laser
        sits at the robot origin (:attr:`laser_offset` = 0), so this is the laser's pose
        and the robot's pose alike.
    ranges : ndarray, shape (S, B)
        Measured ranges [m], B = 180. A reading equal to :attr:`max_range` means no return.
    beam_angles : ndarray, shape (B,)
        Beam directions relative to the heading [rad], counter-clockwise: beam ``i`` points
        at :math:`\theta - \pi/2 + i\,\pi/180`, i.e. −90°, −89°, …, +89° (the CARMEN
        convention for 180-beam FLASER, checked against scan alignment; a start at −89.5°
        fits the data almost as well).
    odometry : ndarray, shape (S − 1, 2, 3)
        The log's real odometry between scans: the pair (corrected pose of scan k, last
        ``ODOM`` pose before scan k + 1). The log's ``ODOM`` lines are the corrected pose of
        the last scan continued by wheel-odometry increments (reset after every scan), so
        this pair is what the wheels measured over the step, in a frame anchored at the
        corrected pose of scan k; its end misses the next corrected pose by a median of 5 cm.
    max_range : float
        81.83 m: the value the scanner writes for "no return" (SICK LMS). The largest
        genuine reading is 25.38 m, so a beam model may prefer a smaller :math:`z_{max}`
        with these readings mapped to it.
    laser_offset : float
        Forward offset of the laser from the robot origin [m], from the log's
        ``PARAM robot_frontlaser_offset`` line (0.0).
    neff : ndarray, shape (S,)
        GMapping's effective particle count logged after each scan (2.1 … 15).
    folder : str
        The folder the log was read from.
    """

    neff: np.ndarray = field(default_factory=lambda: np.empty(0))

    def __repr__(self) -> str:
        return _summary(self, ["t", "poses", "ranges", "beam_angles", "max_range", "folder"])


_INTEL_MAX_RANGE = 81.83


def _carmen_fields(parsed: dict, max_range: float) -> dict:
    # checked finite by _parse_carmen
    laser_offset = float(parsed["params"].get("robot_frontlaser_offset", 0.0))
    out = {k: np.ascontiguousarray(parsed[k]) for k in ("t", "poses", "ranges", "odometry")}
    out["beam_angles"] = parsed["beam_angles"]
    _readonly(*out.values())
    return dict(out, max_range=max_range, laser_offset=laser_offset)


@functools.lru_cache(maxsize=2)
def _intel_cached(file: Path, stamp: tuple) -> IntelLab:
    del stamp  # part of the cache key only
    _verify(_INTEL, file)
    with gzip.open(file, "rt", encoding="ascii") as fh:
        lines = fh.read().splitlines()
    try:
        parsed = _parse_carmen(lines)
    except _CarmenError as exc:
        raise DatasetCorruptError(
            f"{file}: {exc}", file=str(file), url=_INTEL.files[0].url
        ) from None
    if (
        "robot_frontlaser_offset" not in parsed["params"]
        or parsed["neff"].size != parsed["t"].size
    ):
        raise DatasetCorruptError(
            f"{file}: unexpected CARMEN layout", file=str(file), url=_INTEL.files[0].url
        )
    neff = parsed["neff"]
    _readonly(neff)
    return IntelLab(**_carmen_fields(parsed, _INTEL_MAX_RANGE), folder=str(file.parent), neff=neff)


def read_carmen_log(path, *, max_range=None) -> CarmenLog:
    r"""Read any CARMEN laser log (``FLASER`` scans and ``ODOM`` odometry), e.g. Radish's logs.

    The same arrays as :func:`load_intel_lab` (see :class:`CarmenLog`), for a log the reader
    brings: no checksum is checked. Lines other than ``FLASER``, ``ODOM``, ``NEFF`` and
    ``PARAM`` are skipped; a malformed one raises ``ValueError`` with its line number and
    what was expected there.

    Parameters
    ----------
    path : str or os.PathLike
        The log file (plain text, or gzip-compressed if its name ends in ``.gz``).
    max_range : float, optional
        The scanner's no-return code [m]. Default: the largest range in the log, if it occurs
        more than once (a code repeats; a genuine longest reading rarely does); otherwise the
        argument is required.

    Returns
    -------
    CarmenLog
    """
    try:
        file = Path(os.fspath(path)).expanduser()
    except TypeError as exc:
        raise ValueError(
            f"path must be a file name (str or os.PathLike), got {type(path).__name__} {path!r}"
        ) from exc
    if not file.is_file():
        raise FileNotFoundError(f"path: no such file {str(file)!r}")
    import zlib  # here, not at the top: this reader's errors only

    max_range = _carmen_max_range(max_range)
    opener = gzip.open if file.suffix == ".gz" else open
    try:
        with opener(file, "rt", encoding="ascii", errors="strict") as fh:
            lines = fh.read().splitlines()
    except (UnicodeDecodeError, OSError, EOFError, zlib.error) as exc:
        # EOFError: a gzip file cut short; zlib.error: its compressed data corrupt
        raise ValueError(
            f"path: {str(file)!r} is not a readable text CARMEN log ({type(exc).__name__}: {exc})"
        ) from None
    try:
        parsed = _parse_carmen(lines)
    except _CarmenError as exc:
        raise ValueError(f"{file}: {exc}") from None
    if max_range is None:
        ranges = parsed["ranges"]
        max_range = float(ranges.max())
        if np.count_nonzero(ranges == max_range) < 2:
            raise ValueError(
                f"max_range: pass the scanner's no-return code; the log's largest reading, "
                f"{max_range!r} m, occurs once, so it is a reading, not a code"
            )
    return CarmenLog(**_carmen_fields(parsed, max_range), folder=str(file.parent))


def _carmen_max_range(value) -> float | None:
    """``read_carmen_log``'s ``max_range``: None, or one finite positive real number (a
    0-d array too; not a bool, a string, a list or an array of several)."""
    if value is None:
        return None
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        arr = np.asarray(None)
    if arr.dtype.kind == "c":
        raise TypeError(f"max_range must be real, got complex {value!r}")
    if arr.dtype.kind not in "iuf" or arr.ndim != 0:
        raise ValueError(
            f"max_range must be one positive number of metres, got {type(value).__name__} "
            f"{value!r}"
        )
    number = float(arr)
    if not (np.isfinite(number) and number > 0):
        raise ValueError(f"max_range must be a positive number of metres, got {number!r}")
    return number


def load_intel_lab(path=None) -> IntelLab:
    r"""Load the Intel Research Lab corrected laser log (folder ``intel_lab_corrected``).

    910 scans of 180 beams (1° apart over 180°) recorded by a robot in the Intel Research
    Lab, Seattle, each at a SLAM-corrected pose — the data for building a map and testing
    the beam and likelihood-field models against it (Probabilistic Robotics, Secs. 6.3–6.4,
    Tables 6.1–6.3). Credit Radish (A. Howard and N. Roy, 2003) and Dirk Hähnel; if you use
    the corrected poses, also G. Grisetti, C. Stachniss, W. Burgard, IEEE T-RO 23(1), 2007.

    Returns the laser's poses (equal to the robot's: the log's laser offset is 0), the
    ranges in metres, the beam angles relative to the heading and the max-range code; see
    :class:`IntelLab`.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The dataset folder, or a folder holding it; then nothing is downloaded. Default:
        ``$PROBROB_DATA``, then ``shared/data`` beside the repository, then the download
        cache, downloading a missing file into it.

    Returns
    -------
    IntelLab

    Raises
    ------
    DatasetNotFoundError, DatasetCorruptError, ValueError
        As :func:`load_mrclam`.
    """
    name = _INTEL.files[0].name
    file = _locate(_INTEL, (name,), path)[name]
    return _intel_cached(file, _stamp(file))


# --------------------------------------------------------------------------- LNPR wall


@dataclass(frozen=True, eq=False)
class LNPRWall:
    r"""Ueda's wall-facing LiDAR and IR log, as returned by :func:`load_lnpr_wall`.

    All arrays are read-only.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Seconds since the first reading (from the logged local date and time, 1 s
        resolution); strictly increasing, a reading every ~3 s.
    lidar : ndarray, shape (n,)
        LiDAR range to the wall [m] (logged in whole millimetres).
    ir : ndarray, shape (n,)
        Raw infrared light-sensor value (unitless ADC count).
    true_distance : float
        The **nominal** wall distance [m], 0.2 or 0.6. The measured means are 10–27 mm
        longer, so the true distance is only approximately known.
    distance_mm : int
        The nominal distance in millimetres (200 or 600), as in the file name.
    local_time : ndarray of datetime64[s], shape (n,)
        The logged date and time, local to the logging machine (probably JST, not stated).
    hour : ndarray, shape (n,)
        Local time of day in hours, in [0, 24) — for the time-of-day drift SOURCE.md shows.
    folder : str
        The folder the file was read from.
    """

    t: np.ndarray
    lidar: np.ndarray
    ir: np.ndarray
    true_distance: float
    distance_mm: int
    local_time: np.ndarray
    hour: np.ndarray
    folder: str

    def __repr__(self) -> str:
        return _summary(self, ["t", "lidar", "ir", "true_distance", "folder"])


@functools.lru_cache(maxsize=4)
def _lnpr_cached(file: Path, stamp: tuple, distance_mm: int) -> LNPRWall:
    del stamp  # part of the cache key only
    _verify(_LNPR, file)
    a = np.loadtxt(file, dtype=np.int64, ndmin=2)
    if a.shape[1] != 4:
        raise DatasetCorruptError(
            f"{file}: expected 4 columns", file=str(file), url=_LNPR.file(file.name).url
        )
    date, hms = a[:, 0], a[:, 1]
    days = np.empty(date.size, dtype="datetime64[D]")
    for d in np.unique(date).tolist():  # a handful of distinct dates
        days[date == d] = np.datetime64(f"{d // 10000:04d}-{d // 100 % 100:02d}-{d % 100:02d}")
    seconds = (hms // 10000) * 3600 + (hms // 100 % 100) * 60 + hms % 100
    local_time = days.astype("datetime64[s]") + seconds.astype("timedelta64[s]")
    out = dict(
        t=(local_time - local_time[0]).astype(np.int64).astype(float),
        lidar=a[:, 3] / 1000.0,
        ir=a[:, 2].astype(float),
        local_time=local_time,
        hour=seconds / 3600.0,
    )
    _readonly(*out.values())
    return LNPRWall(
        **out,
        true_distance=distance_mm / 1000.0,
        distance_mm=distance_mm,
        folder=str(file.parent),
    )


_LNPR_DISTANCES = (200, 600)


def load_lnpr_wall(distance_mm=200, path=None) -> LNPRWall:
    r"""Load a LNPR wall log: one LiDAR beam (and an IR sensor) facing a wall.

    A small robot (from memory a Raspberry Pi Mouse with a Hokuyo URG LiDAR; not stated in
    the source) faced a wall at a fixed distance and logged one reading about every 3 s for
    2–3 days: 58,988 readings at 200 mm, 82,301 at 600 mm (folder ``lnpr_wall_lidar``). The
    readings are clean (within ±20 mm of the mean: no short, max-range or random readings),
    which makes them a sanity check for fitting :math:`\sigma_{hit}` and for EM
    (Probabilistic Robotics, Table 6.2), and a real example of noise that drifts with the
    time of day. Cite R. Ueda, 『詳解 確率ロボティクス』, Kodansha, 2019, and
    github.com/ryuichiueda/LNPR_BOOK_CODES (MIT, © 2019 Ryuichi Ueda).

    Parameters
    ----------
    distance_mm : {200, 600}
        The nominal wall distance, selecting ``sensor_data_<distance_mm>.txt``.
    path : str or os.PathLike, optional
        The dataset folder, or a folder holding it; then nothing is downloaded. Default:
        ``$PROBROB_DATA``, then ``shared/data`` beside the repository, then the download
        cache, downloading a missing file into it.

    Returns
    -------
    LNPRWall
        Ranges in metres, times in seconds.

    Raises
    ------
    ValueError
        ``distance_mm`` is not 200 or 600, or ``path`` is not a folder.
    DatasetNotFoundError, DatasetCorruptError
        As :func:`load_mrclam`.
    """
    if (
        isinstance(distance_mm, bool)
        or not isinstance(distance_mm, int | np.integer)
        or int(distance_mm) not in _LNPR_DISTANCES
    ):
        raise ValueError(
            f"distance_mm must be one of {_LNPR_DISTANCES} (the recorded wall distances), "
            f"got {distance_mm!r}"
        )
    name = f"sensor_data_{int(distance_mm)}.txt"
    file = _locate(_LNPR, (name,), path)[name]
    return _lnpr_cached(file, _stamp(file), int(distance_mm))
