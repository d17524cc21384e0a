"""Output files: one check before the work, one atomic writer after it.

Every file gfrf writes for the user (tables, figures, report pages, CSV traces, model
files) is checked by :func:`check_output_path` before any computation and written by
:func:`atomic_open` (or its wrappers :func:`atomic_write_text`, :func:`atomic_write_bytes`
and :func:`atomic_write_figure`), which opens the output exactly once:

- a regular file (or a new one) is written to a hidden temporary file in its folder and
  moved over it with :func:`os.replace` only once complete: a run that fails or is
  interrupted (Ctrl-C) midway leaves the previous file untouched and no partial file;
- a path that resolves to something that is not a regular file (``/dev/null``, a FIFO,
  a terminal, ``/dev/stdout`` redirected to a file elsewhere) is opened once and written
  in place, never replaced, so a device stays a device, a symbolic link stays a link and
  a write error (no space left) is reported;
- a symbolic link to a regular file in the same folder keeps the link: the file it
  points to is replaced; a symbolic link to a regular file in another folder is
  written in place (as the shell's ``>`` would), a dangling one is refused.

Every error names the user's path, never the temporary file's.

>>> import tempfile, pathlib
>>> target = pathlib.Path(tempfile.mkdtemp()) / "table.csv"
>>> _ = atomic_write_text(target, "a,b\\n1,2\\n")
>>> target.read_text()
'a,b\\n1,2\\n'
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import stat
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from gfrf.errors import ArgumentError

__all__ = ["check_output_path", "atomic_open", "atomic_write_text", "atomic_write_bytes",
           "atomic_write_figure"]


def _umask() -> int:
    """The process umask (read by setting and restoring it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _plan(path: str | os.PathLike[str]) -> tuple[str, Path, os.stat_result | None]:
    """How to write ``path``: ``("replace", file, stat)`` or ``("inplace", path, stat)``.

    Raises
    ------
    OSError
        A directory, a dangling symbolic link, or a path that cannot be examined.
    """
    target = Path(path)
    try:
        st: os.stat_result | None = os.stat(target)  # follows symbolic links
    except FileNotFoundError:
        st = None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", str(target))
    if st is not None and not stat.S_ISREG(st.st_mode):
        return "inplace", target, st  # a device, FIFO, terminal or socket
    if not target.is_symlink():
        return "replace", target, st
    resolved = Path(os.path.realpath(target))
    if st is None:
        raise FileNotFoundError(errno.ENOENT, "a symbolic link to nothing (gfrf does not "
                                "create the file a link points to)", str(target))
    if resolved.parent == Path(os.path.realpath(target.parent)):
        return "replace", resolved, st  # the link stays a link
    return "inplace", target, st  # elsewhere: written through the link, as ``>`` does


def check_output_path(option: str, path: str | os.PathLike[str] | None) -> None:
    """Refuse, before any work, an output file that cannot be written.

    An empty name, a directory, a dangling symbolic link, a file whose folder does not
    exist or is not writable, or a device/FIFO that is not writable.

    Parameters
    ----------
    option : str
        The option or argument that named the file (``"--csv"``), for the message.
    path : str, path-like or None
        The output file; ``None`` checks nothing.

    Raises
    ------
    ArgumentError
        Naming ``option`` and the user's ``path``.
    """
    if path is None:
        return
    text = os.fspath(path)
    if not text.strip():
        raise ArgumentError(f"{option}: empty file name")
    try:
        how, target, st = _plan(text)
    except IsADirectoryError:
        raise ArgumentError(f"{option} {text!r} is a directory") from None
    except OSError as exc:
        raise ArgumentError(f"{option} {text!r}: {exc.strerror or exc}") from None
    if how == "inplace":
        if not os.access(target, os.W_OK):
            raise ArgumentError(f"{option} {text!r}: not writable")
        return
    folder = target.parent
    if not folder.is_dir():
        raise ArgumentError(f"{option} {text!r}: the folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ArgumentError(f"{option} {text!r}: the folder {str(folder)!r} is not writable")


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w",
                encoding: str | None = "utf-8", newline: str | None = None, *,
                permissions: int | None = None) -> Iterator[IO[Any]]:
    """Open ``path`` once for writing; on success the content replaces it atomically.

    The temporary file lives in the folder of the file replaced (so the final
    :func:`os.replace` is a rename on one file system) and is removed if the block
    raises anything, ``KeyboardInterrupt`` included.  The new file gets the permissions
    of the file it replaces, or the usual ``0o666 & ~umask`` of a new file.  A path that
    resolves to a device, FIFO or terminal is opened once and written in place.

    Parameters
    ----------
    path : str or path-like
        The final file.
    mode : {"w", "wb"}
        Text or binary.
    encoding : str or None
        Encoding of a text file (ignored for ``"wb"``).
    newline : str or None
        As for :func:`open` (ignored for ``"wb"``).
    permissions : int or None, optional
        The replacing file's permission bits (``0o600`` for a private cache); None keeps
        those of the file it replaces, or ``0o666 & ~umask`` for a new one.

    Yields
    ------
    file object
        Where to write the content.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open writes with mode 'w' or 'wb', got {mode!r}")
    binary = mode == "wb"
    kwargs: dict[str, Any] = {} if binary else {"encoding": encoding, "newline": newline}
    user = Path(path)
    try:
        how, target, st = _plan(user)
    except OSError as exc:
        raise _named(exc, user) from None
    if how == "inplace":
        try:
            with _open_in_place(target, st, mode, kwargs) as fh:
                yield fh
        except OSError as exc:
            raise _named(exc, user) from None
        return
    try:
        fd, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.",
                                    suffix=f".tmp{target.suffix}")
    except OSError as exc:
        raise _named(exc, user) from None
    tmp = Path(name)
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        if permissions is None:
            permissions = stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~_umask()
        os.chmod(tmp, permissions)
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError):
            raise _named(exc, user) from None
        raise


def _open_in_place(target: Path, st: os.stat_result | None, mode: str,
                   kwargs: dict[str, Any]) -> IO[Any]:
    """``target`` opened once for writing; the process's own stdout or stderr (``/dev/stdout``
    with stdout redirected to a file) is written through its descriptor, after what was
    printed, so the shell's file gets the data followed by the text, not one over the other."""
    for stream in (sys.stdout, sys.stderr):
        try:
            fd = stream.fileno()
            same = st is not None and os.path.samestat(st, os.fstat(fd))
        except (AttributeError, OSError, ValueError):
            continue
        if same:
            stream.flush()
            return os.fdopen(os.dup(fd), mode, **kwargs)
    return open(target, mode, **kwargs)


def _named(exc: OSError, target: Path) -> OSError:
    """``exc`` about ``target`` (the user's path), not a temporary file."""
    if exc.errno is None:
        return exc
    return type(exc)(exc.errno, exc.strerror or os.strerror(exc.errno), str(target))


def atomic_write_text(path: str | os.PathLike[str], text: str,
                      encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_open`); return the path.

    Parameters
    ----------
    path : str or path-like
        The final file.
    text : str
        Its content.
    encoding : str
        Text encoding.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_open(path, "w", encoding=encoding) as fh:
        fh.write(text)
    return Path(path)


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes, *,
                       permissions: int | None = None) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_open`); return the path.

    Parameters
    ----------
    path : str or path-like
        The final file.
    data : bytes
        Its content.
    permissions : int or None, optional
        The file's permission bits (see :func:`atomic_open`).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_open(path, "wb", permissions=permissions) as fh:
        fh.write(data)
    return Path(path)


def atomic_write_figure(fig: Any, path: str | os.PathLike[str], **savefig: Any) -> Path:
    """Render a matplotlib figure to memory, then write it once (see :func:`atomic_open`).

    Rendering to a buffer first lets every format reach a FIFO or a terminal (some
    writers seek) and leaves no partial file when rendering fails.  Every text of the
    figure is drawn as plain text (no mathtext, no LaTeX): gfrf's labels use none, and
    a ``$`` in a model's name stays a dollar sign.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (not closed here).
    path : str or path-like
        The final file; its suffix is the format unless ``format=`` is given.
    **savefig
        Passed to :meth:`~matplotlib.figure.Figure.savefig`.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    for text in fig.findobj(lambda artist: hasattr(artist, "set_parse_math")):
        text.set_usetex(False)  # user text is data: no mathtext, no LaTeX
        text.set_parse_math(False)
    buffer = io.BytesIO()
    savefig.setdefault("format", Path(path).suffix.lstrip(".").lower() or None)
    fig.savefig(buffer, **savefig)
    return atomic_write_bytes(path, buffer.getvalue())
