"""Atomic output files: write a temporary file next to the target, then rename it.

Every file gfrf writes for the user (tables, figures, report pages, CSV traces) goes
through :func:`atomic_path`: the content is written to a hidden temporary file in the
target's directory and moved over the target with :func:`os.replace` only once it is
complete.  A run that fails or is interrupted (Ctrl-C) midway leaves the previous file
untouched and no partial file behind.  A target that exists and is not a regular file
(``/dev/null``, ``/dev/full``, a FIFO, a terminal) is written in place, never replaced, so
a device stays a device and a write error (``/dev/full``: no space) is reported.  Every
error names the user's path, never the temporary file's.

>>> import tempfile, pathlib
>>> target = pathlib.Path(tempfile.mkdtemp()) / "table.csv"
>>> _ = atomic_write_text(target, "a,b\\n1,2\\n")
>>> target.read_text()
'a,b\\n1,2\\n'
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_text"]


def _umask() -> int:
    """The process umask (read by setting and restoring it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces ``path`` atomically.

    The temporary file lives in the directory of ``path`` (so the final
    :func:`os.replace` is a rename on one file system) and keeps its suffix (so
    writers that choose the format by suffix, such as ``savefig``, see the same
    one).  It is removed if the block raises anything, ``KeyboardInterrupt``
    included.  The new file gets the permissions of the file it replaces, or the
    usual ``0o666 & ~umask`` of a new file.

    Parameters
    ----------
    path : str or path-like
        The final file.

    Yields
    ------
    pathlib.Path
        Where to write the content.
    """
    target = Path(path)
    try:
        st: os.stat_result | None = os.stat(target)
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise _named(exc, target) from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", str(target))
    if st is not None and not stat.S_ISREG(st.st_mode):  # a device or FIFO: in place
        try:
            yield target
        except OSError as exc:
            raise _named(exc, target) from None
        return
    try:
        fd, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.",
                                    suffix=f".tmp{target.suffix}")
    except OSError as exc:
        raise _named(exc, target) from None
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        mode = stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~_umask()
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError):
            raise _named(exc, target) from None
        raise


def _named(exc: OSError, target: Path) -> OSError:
    """``exc`` about ``target`` (the user's path), not a temporary file."""
    if exc.errno is None:
        return exc
    return type(exc)(exc.errno, exc.strerror or os.strerror(exc.errno), str(target))


def atomic_write_text(path: str | os.PathLike[str], text: str,
                      encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_path`); return the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)
    return Path(path)
