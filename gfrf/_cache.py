"""The on-disk cache of generated, numba-compiled code, and what it trusts.

A cache is code: numba reads its index files (``*.nbi``) with :mod:`pickle`, which can
run anything, and a Python source file could be swapped for a ``.pyc``.  So gfrf runs
only what it trusts, by these rules (one policy for the compiled kernels,
:mod:`gfrf.kernels.compiled`, and the fast simulation path, :mod:`gfrf.sim.fastsim`):

* The layout is ``ROOT/kernels`` and ``ROOT/fastsim``, ROOT being ``$GFRF_CACHE_DIR``,
  else the platform's user cache directory (``$XDG_CACHE_HOME`` or ``~/.cache`` on Linux,
  ``~/Library/Caches`` on macOS, ``%LOCALAPPDATA%`` on Windows) ``/gfrf``.
* The code that runs is always the source generated in this process, compiled from the
  string (:func:`load_generated`): a file in the cache is only the anchor that numba's
  cache is keyed to, rewritten (through :func:`tempfile.mkstemp` and :func:`os.replace`,
  never a predictable name) when its text differs.  No file is imported.
* numba keeps the machine code in the ``__pycache__`` folder next to the anchor.  That
  folder and the anchor's folder are created with mode 0700 and checked on every use
  (:func:`private_folder`): they must be real directories (not symbolic links) owned by
  this user and not writable by group or others, every entry in them likewise (a
  regular file or folder of this user's, not group/world writable), and every folder
  above them owned by this user or root and not writable by group or others unless it
  has the sticky bit (like ``/tmp``).  With ``NUMBA_CACHE_DIR`` set (common on clusters
  and in containers) numba keeps the machine code under that folder instead
  (``$NUMBA_CACHE_DIR/<the anchor folder's path>``): that folder is created with mode
  0700 and passes the same checks (itself and its entries; every folder above it) before
  numba reads anything from it.  ``NUMBA_CACHE_LOCATOR_CLASSES`` (numba's own choice of
  locators, whose folders gfrf cannot know before numba reads them) turns gfrf's caching
  off.  When a check fails, one line ``gfrf: warning: ...`` says why and the code is
  compiled in memory, uncached.

What this does not protect against: a process running as the same user (or root) can
write the cache folder, and equally the user's ``site-packages`` or shell startup files;
the cache is exactly as trusted as the user's own account.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
import types
import warnings
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

__all__ = ["cache_root", "private_folder", "load_generated", "trust_dispatchers"]

#: Largest anchor file read back to compare with the generated source (bytes).
_MAX_ANCHOR = 16 * 1024 * 1024


def cache_root() -> Path:
    """``$GFRF_CACHE_DIR``, else the platform's user cache directory ``/gfrf``."""
    base = os.environ.get("GFRF_CACHE_DIR")
    if base:
        return Path(base)
    if sys.platform == "win32":
        root = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        root = Path.home() / "Library" / "Caches"
    else:
        root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "gfrf"


def _uid() -> int | None:
    return os.getuid() if hasattr(os, "getuid") else None


def _problem(path: str, st: os.stat_result, *, above: bool, sticky: bool = True
             ) -> str | None:
    """Why ``path`` (its :func:`os.lstat`) is not to be trusted, or None.

    ``above``: root may own it too and, if ``sticky``, a sticky folder (``/tmp``) may
    be writable by others."""
    uid = _uid()
    if uid is None:  # Windows: no owner bits to check
        return None
    if stat.S_ISLNK(st.st_mode):
        return f"{path} is a symbolic link"
    owners = (uid, 0) if above else (uid,)
    if st.st_uid not in owners:
        return f"{path} is owned by uid {st.st_uid}, not by this user (uid {uid})"
    writable = st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)
    if writable and not (above and sticky and st.st_mode & stat.S_ISVTX):
        return (f"{path} is writable by group or others "
                f"(mode {stat.S_IMODE(st.st_mode):04o})")
    return None


def _check_above(folder: Path) -> str | None:
    """Check every folder from / down to ``folder`` (its real path) itself."""
    parts = folder.parts
    for i in range(1, len(parts) + 1):
        path = os.path.join(*parts[:i])
        if problem := _problem(path, os.stat(path), above=True):
            return problem
    return None


def _check_private(folder: Path) -> str | None:
    """``folder`` and each entry in it: this user's, not group/world writable, no link."""
    st = os.lstat(folder)
    if problem := _problem(str(folder), st, above=False):
        return problem
    if not stat.S_ISDIR(st.st_mode):
        return f"{folder} is not a directory"
    with os.scandir(folder) as entries:
        for entry in entries:
            st = entry.stat(follow_symlinks=False)
            if problem := _problem(entry.path, st, above=False):
                return problem
            if not (stat.S_ISREG(st.st_mode) or stat.S_ISDIR(st.st_mode)):
                return f"{entry.path} is not a regular file"
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"{folder} is not writable"
    return None


def _numba_redirect() -> str | None:
    """The numba setting that would keep the cache in folders gfrf cannot check first."""
    from numba.core import config

    if getattr(config, "CACHE_LOCATOR_CLASSES", ""):
        return "NUMBA_CACHE_LOCATOR_CLASSES is set"
    return None


def _numba_folder(anchor: Path) -> Path:
    """Where numba keeps the machine code of functions defined in ``anchor``: the
    ``__pycache__`` beside it, or with ``NUMBA_CACHE_DIR`` set numba's folder under it."""
    from numba.core import config

    if not getattr(config, "CACHE_DIR", ""):
        return anchor.parent / "__pycache__"
    from numba.core.caching import UserProvidedCacheLocator

    subpath = UserProvidedCacheLocator.get_suitable_cache_subpath(str(anchor))
    root = str(config.CACHE_DIR)  # type: ignore[attr-defined]
    return Path(os.path.realpath(os.path.join(root, subpath)))


def _user_cache_folder(folder: Path) -> str | None:
    """Create ``folder`` (mode 0700) under ``NUMBA_CACHE_DIR`` and check it as
    :func:`private_folder` checks its own: why it is not to be trusted, or None."""
    try:
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
        return _check_above(folder.parent) or _check_private(folder)
    except OSError as exc:
        return f"{exc.strerror or exc}: {exc.filename or folder}"


def private_folder(kind: str, *, numba: bool = True) -> Path | None:
    """The checked cache folder ``ROOT/kind`` (created 0700 with its ``__pycache__``).

    Returns None, after one ``UserWarning`` saying why, when the folder cannot be made
    or fails a check of the module docstring's trust model; the caller then compiles in
    memory, uncached.

    Parameters
    ----------
    kind : str
        ``"kernels"`` or ``"fastsim"``.
    numba : bool, optional
        Also refuse when numba's settings would keep its cache elsewhere (imports numba);
        False for files numba never reads (:mod:`gfrf.kernels.native`).
    """
    root = cache_root()
    try:
        root.mkdir(parents=True, exist_ok=True, mode=0o700)
        folder = Path(os.path.realpath(root)) / kind
        problem = _check_above(folder.parent)
        if problem is None:
            for path in (folder, folder / "__pycache__"):
                with contextlib.suppress(FileExistsError):
                    path.mkdir(mode=0o700)
                if problem := _check_private(path):
                    break
        problem = problem or (_numba_redirect() if numba else None)
    except OSError as exc:
        problem = f"{exc.strerror or exc}: {exc.filename or root}"
    if problem is None:
        return folder
    warnings.warn(f"gfrf's cache is not used ({problem}): compiling in memory, uncached "
                  "(the cache folder must be this user's and writable by nobody else)",
                  UserWarning, stacklevel=3)
    return None


def _write_anchor(folder: Path, name: str, source: str) -> Path:
    """``folder/name`` holding ``source`` (rewritten through a mkstemp file if not)."""
    path = folder / name
    data = source.encode("utf-8")
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except FileNotFoundError:
        current = None
    else:
        with os.fdopen(fd, "rb") as f:
            current = f.read(_MAX_ANCHOR)
    if current != data:  # absent, stale or tampered with: ours replaces it
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{name}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise
    return path


def load_generated(kind: str, name: str, make_source: Callable[[bool], str]) -> types.ModuleType:
    """Run generated source as module ``name``, with numba's disk cache when trusted.

    Parameters
    ----------
    kind : str
        Cache folder (``"kernels"``, ``"fastsim"``).
    name : str
        Module name (unique per source: it carries the source's hash).
    make_source : callable
        ``make_source(cache) -> str``: the module source, with numba's ``cache=cache``.

    Returns
    -------
    types.ModuleType
        The module, registered in :data:`sys.modules` (numba's cache refers to it by
        name).  Its code is always compiled from ``make_source``'s string; the anchor
        file only gives numba's cache a place (see the module docstring).  When running
        it with the cache fails (a truncated or damaged ``.nbi``/``.nbc`` file: numba
        raises on the pickle), the module's cache files are deleted and it runs once
        more, compiling afresh.
    """
    folder = private_folder(kind)
    path: Path | None = None
    machine_code: Path | None = None
    if folder is not None:  # numba's folder, checked before numba reads from it
        machine_code = _numba_folder(folder / f"{name}.py")
        if machine_code != folder / "__pycache__" and (
                problem := _user_cache_folder(machine_code)):
            warnings.warn(f"gfrf's cache is not used ({problem}; NUMBA_CACHE_DIR is set): "
                          "compiling in memory, uncached", UserWarning, stacklevel=2)
            folder = None
    source = make_source(folder is not None)
    if folder is not None:
        try:
            path = _write_anchor(folder, f"{name}.py", source)
        except OSError as exc:
            warnings.warn(f"gfrf's cache is not used ({exc.strerror or exc}: "
                          f"{exc.filename or folder}): compiling in memory, uncached",
                          UserWarning, stacklevel=2)
            source = make_source(False)
    filename = str(path) if path else f"<gfrf {name}>"
    code = compile(source, filename, "exec")
    try:
        module = _run(name, filename, code)
    except Exception:  # a damaged cache file (a truncated pickle): discarded, run again
        if path is None or machine_code is None:
            raise
        for stale in machine_code.glob(f"{name}.*"):
            with contextlib.suppress(OSError):
                stale.unlink()
        module = _run(name, filename, code)
    if path is not None and machine_code is not None:
        _keep_in(module, machine_code)
    return module


def _run(name: str, filename: str, code: types.CodeType) -> types.ModuleType:
    """A new module ``name`` (registered in :data:`sys.modules`) running ``code``."""
    module = types.ModuleType(name)
    module.__file__ = filename
    sys.modules[name] = module
    try:
        exec(code, module.__dict__)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def _keep_in(module: types.ModuleType, folder: Path) -> None:
    """Turn off the disk cache of any lazily compiled numba function of ``module`` whose
    cache numba did not put in the checked ``folder`` (numba's locators are chosen
    per function; this makes sure no other folder's pickles are read)."""
    from numba.core.caching import NullCache

    for value in list(vars(module).values()):
        cache = getattr(value, "_cache", None)
        if cache is None or isinstance(cache, NullCache):
            continue
        if os.path.realpath(getattr(cache, "cache_path", "")) != os.path.realpath(folder):
            value._cache = NullCache()


def trust_dispatchers(dispatchers: Iterable[Any]) -> None:
    """Turn off numba's disk cache of ``dispatchers`` whose cache folder fails the checks.

    For numba functions of gfrf's own package (``cache=True`` in a source file, such as
    :mod:`gfrf.bounds.jet_kernels`): numba puts their cache next to the package or in
    a user-wide folder; each must pass the same checks as :func:`private_folder`
    (folders above it owned by this user or root) before its pickles are read.  Call
    before the first call of each dispatcher (numba loads its cache then).

    Parameters
    ----------
    dispatchers : iterable of numba dispatchers
        The ``@njit(cache=True)`` functions.
    """
    from numba.core.caching import NullCache

    for dispatcher in dispatchers:
        cache = getattr(dispatcher, "_cache", None)
        if cache is None or isinstance(cache, NullCache):
            continue
        problem = _numba_redirect()
        try:
            folder = Path(os.path.realpath(cache.cache_path))
            problem = problem or _check_above(folder.parent) or _check_folder_above(folder)
        except (OSError, AttributeError) as exc:
            problem = str(exc)
        if problem:
            dispatcher._cache = NullCache()
            warnings.warn(f"numba's cache of {dispatcher.__name__} is not used ({problem}): "
                          "compiling in memory", UserWarning, stacklevel=2)


def _check_folder_above(folder: Path) -> str | None:
    """The folder numba keeps a package's cache in, and its entries (owned by this user
    or root, not group/world writable)."""
    if problem := _problem(str(folder), os.lstat(folder), above=True, sticky=False):
        return problem
    with os.scandir(folder) as entries:
        for entry in entries:
            if problem := _problem(entry.path, entry.stat(follow_symlinks=False),
                                   above=True, sticky=False):
                return problem
    return None
