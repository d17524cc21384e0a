"""Compiled kernels as shared libraries, which a later process loads without numba.

numba's own disk cache still costs a second process about 0.6 s for any kernel: numba's
import (0.2 s) and its target set-up (its typing registries, and scipy.linalg for its
BLAS check) before it reads a single cached function.  So where a C compiler driver is
at hand (``cc`` on Linux), the kernel's loop is compiled once by numba (no exceptions:
``error_model="numpy"``), its machine code emitted by LLVM as a position-independent
object, linked by ``cc -shared`` into ``gfrf_native_<hash>.so`` in the checked cache
folder (:func:`gfrf._cache.private_folder`, the same trust as numba's own cache, whose
pickles run code too) and called through :mod:`ctypes`: a later process generates the
kernel's source (to find its hash), imports llvmlite (the host CPU's name and
features, part of the hash) and opens the library, about 0.1-0.2 s in all.  The
process that compiles calls the same library, so the bits never depend on the state
of the cache.  Without ``cc`` the object file itself is kept (``gfrf_native_<hash>.o``)
and linked in memory by LLVM (llvmlite's MCJIT, the same machine code) when loaded:
about 0.05 s more than opening a library, and still no numba.  On another system, or
when any step fails, the caller uses numba's cache
(:func:`gfrf.kernels.compiled.numba_ufunc`).

Each library or object file has a record beside it (``<file>.json``: the layout, its
size in bytes and its SHA-256), both written by :func:`gfrf._atomic.atomic_write_bytes`
once the build is complete.  A file is loaded only when its size and hash match the
record: a truncated or altered file (dynamic loading of a truncated library crashes the
process, with a bus error or a segmentation fault) or a missing or unreadable record is
a cache miss, silently, like an absent file: both are deleted and the kernel is built
again.  The object file is linked from the very bytes that were checked.
"""

from __future__ import annotations

import contextlib
import ctypes
import hashlib
import importlib.metadata
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import types
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._atomic import atomic_write_bytes
from gfrf.kernels.realcode import FASTMATH

__all__ = ["NativeKernel", "native_kernel"]

#: Name of the loop's symbol in the shared library.
SYMBOL = "gfrf_kernel_loop"
#: Layout of the library and of its calling convention (part of the hash).
FORMAT = "1"
#: Largest record file read (bytes); a longer one is not gfrf's and is a cache miss.
_MAX_RECORD = 4096


class NativeKernel:
    """``f(w1, .., wn) -> complex128`` over broadcast arrays, by the library's loop.

    Parameters
    ----------
    path : pathlib.Path
        The shared library (``.so``) or object file (``.o``).
    n : int
        The number of arguments (the kernel's order).
    data : bytes
        The file's content, checked against its record (an object file is linked from
        these bytes, a library opened by its path).
    """

    def __init__(self, path: Path, n: int, data: bytes) -> None:
        self.n = n
        if path.suffix == ".o":  # no linker here: the object linked in memory by LLVM
            import llvmlite.binding as llvm

            llvm.initialize_native_target()
            llvm.initialize_native_asmprinter()
            machine = llvm.Target.from_default_triple().create_target_machine()
            self.library = llvm.create_mcjit_compiler(llvm.parse_assembly(""), machine)
            self.library.add_object_file(llvm.ObjectFileRef.from_data(data))
            self.library.finalize_object()
            address = self.library.get_function_address(SYMBOL)
            if not address:
                raise OSError(f"no {SYMBOL} in {path}")
            prototype = ctypes.CFUNCTYPE(ctypes.c_int32, *([ctypes.c_void_p] * (n + 3)),
                                         ctypes.c_int64)
            self.loop = prototype(address)
        else:
            self.library = ctypes.CDLL(str(path))
            self.loop = getattr(self.library, SYMBOL)
            self.loop.restype = ctypes.c_int32
            self.loop.argtypes = [ctypes.c_void_p] * (n + 3) + [ctypes.c_int64]

    def __call__(self, *w: Any) -> Any:
        """H_n at the broadcast arguments (rad/s): an array of their shape, a scalar for
        scalars, like a numpy ufunc.  ZeroDivisionError at a point on a pole (as
        numba's ufunc raised)."""
        if len(w) != self.n:
            raise TypeError(f"the kernel takes {self.n} arguments, got {len(w)}")
        arrays = [np.ascontiguousarray(a).reshape(-1) for a in
                  np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in w))]
        shape = np.broadcast_shapes(*(np.shape(x) for x in w))
        out = np.empty(math.prod(shape), dtype=np.complex128)
        status, exception = ctypes.c_void_p(), ctypes.c_void_p()
        if self.loop(ctypes.byref(status), ctypes.byref(exception),
                     *(a.ctypes.data for a in arrays), out.ctypes.data, out.size) != 0:
            # the only exception of the kernel's arithmetic: a complex division by zero
            raise ZeroDivisionError("a frequency point on a pole of the kernel")
        return out.reshape(shape) if shape else out[0]


def _loop_source(parts: tuple[str, str], n: int) -> str:
    """Module source of ``kernel_loop(p0, .., p{n-1}, out, count)`` over raw pointers
    (``parts``: :func:`gfrf.kernels.compiled._step_functions`, whose ``@njit(cache=CACHE)``
    lines here compile without exceptions)."""
    args = ", ".join(f"w{i}" for i in range(n))
    return ("from cmath import exp as cmath_exp\n\nfrom numba import njit as _njit, types\n\n"
            "CACHE = False\n\n\ndef njit(**_options):\n"
            f"    return _njit(error_model='numpy', fastmath={FASTMATH!r})\n\n\n"
            f"{parts[0]}\n\n@njit(cache=CACHE)\n{parts[1]}\n\n"
            "_P = types.CPointer(types.float64)\n"
            f"@_njit(types.void({'_P, ' * n}types.CPointer(types.complex128), types.int64),"
            " error_model='numpy')\n"
            f"def kernel_loop({args}, out, count):\n"
            "    for j in range(count):\n"
            f"        out[j] = scalar_kernel({', '.join(f'w{i}[j]' for i in range(n))})\n")


def _host() -> str:
    """The host CPU's name and features as LLVM sees them (the machine code's target)."""
    import llvmlite.binding as llvm

    return f"{llvm.get_host_cpu_name()} {llvm.get_host_cpu_features().flatten()}"


def _record(path: Path) -> Path:
    """The record file of the library or object file ``path``."""
    return path.with_name(path.name + ".json")


def _describe(data: bytes) -> bytes:
    """The record of a file holding ``data``: layout, size and SHA-256, as JSON."""
    return json.dumps({"format": FORMAT, "size": len(data),
                       "sha256": hashlib.sha256(data).hexdigest()}).encode()


def _checked(path: Path) -> bytes | None:
    """The content of ``path`` when its size and SHA-256 match its record; None when
    either file is absent, unreadable or does not match (a cache miss)."""
    try:
        with open(_record(path), "rb") as f:
            record = f.read(_MAX_RECORD + 1)
        size = json.loads(record).get("size") if len(record) <= _MAX_RECORD else None
        if not isinstance(size, int) or os.stat(path).st_size != size:
            return None
        data = path.read_bytes()
    except (OSError, ValueError, AttributeError):  # absent, unreadable, not a JSON object
        return None
    return data if _describe(data) == record else None


def _discard(path: Path) -> None:
    """Delete ``path`` and its record (a failed check: the kernel is built again)."""
    for stale in (path, _record(path)):
        with contextlib.suppress(OSError):
            stale.unlink()


def _build(source: str, target: Path) -> bytes:
    """Compile ``source``'s loop with numba, emit it alone as a PIC object, and link
    ``target`` (a ``.so``) with ``cc``, or keep the object itself (``target`` a ``.o``);
    write ``target`` and then its record atomically and return ``target``'s content."""
    import llvmlite.binding as llvm

    module = types.ModuleType("gfrf_native_build")
    exec(compile(source, "<gfrf native kernel>", "exec"), module.__dict__)
    loop = module.kernel_loop
    result = loop.overloads[loop.signatures[0]]
    ir = llvm.parse_assembly(result.library.get_llvm_str())
    name = result.fndesc.llvm_func_name
    for function in ir.functions:
        if not function.is_declaration:
            function.linkage = (llvm.Linkage.external if function.name == name
                                else llvm.Linkage.internal)
    for variable in ir.global_variables:
        if not variable.is_declaration:
            variable.linkage = llvm.Linkage.internal
    ir.get_function(name).name = SYMBOL
    machine = llvm.Target.from_default_triple().create_target_machine(
        cpu=llvm.get_host_cpu_name(), features=llvm.get_host_cpu_features().flatten(),
        opt=3, reloc="pic", codemodel="default")
    passes = llvm.create_new_module_pass_manager()
    passes.add_global_dead_code_eliminate_pass()  # the Python wrappers and their helpers
    passes.add_strip_dead_prototype_pass()
    passes.run(ir, llvm.create_pass_builder(machine, llvm.create_pipeline_tuning_options()))
    undefined = {f.name for f in ir.functions if f.is_declaration and not f.name.startswith(
        "llvm.")} - {"exp", "sincos", "sin", "cos", "log", "atan2", "hypot", "sqrt", "pow"}
    if undefined:
        raise OSError(f"the kernel's code calls {sorted(undefined)}")
    with tempfile.TemporaryDirectory(dir=target.parent, prefix=".build-") as scratch:
        obj, lib = Path(scratch) / "kernel.o", Path(scratch) / "kernel.so"
        obj.write_bytes(machine.emit_object(ir))
        if target.suffix == ".o":
            lib = obj
        else:
            subprocess.run([shutil.which("cc") or "cc", "-shared", "-o", str(lib), str(obj),
                            "-lm"], check=True, capture_output=True, timeout=600)
        data = lib.read_bytes()
    atomic_write_bytes(target, data, permissions=0o700)
    atomic_write_bytes(_record(target), _describe(data), permissions=0o600)
    return data


def native_kernel(parts: tuple[str, str], n: int) -> NativeKernel | None:
    """The kernel of ``parts`` from its shared library, built first if absent; None when
    no library can be used here (then the caller uses numba's cache).

    Parameters
    ----------
    parts : tuple of str
        :func:`gfrf.kernels.compiled._step_functions` of the kernel.
    n : int
        The kernel's order.

    Returns
    -------
    NativeKernel or None
        The loaded kernel, or None (not Linux, no trusted cache folder, or a failed
        build: the next process tries again).  Without ``cc`` the object file itself is
        kept and linked in memory by LLVM (llvmlite's MCJIT) when loaded.
    """
    if not sys.platform.startswith("linux"):
        return None
    from gfrf._cache import private_folder

    with warnings.catch_warnings():  # numba's cache says why right after, once
        warnings.simplefilter("ignore")
        folder = private_folder("kernels", numba=False)
    if folder is None:
        return None
    source = _loop_source(parts, n)
    try:
        key = "\n".join([FORMAT, platform.machine(), importlib.metadata.version("numba"),
                         _host(), source])
    except (ImportError, importlib.metadata.PackageNotFoundError):
        return None
    suffix = ".o" if shutil.which("cc") is None else ".so"
    path = folder / f"gfrf_native_{hashlib.sha256(key.encode()).hexdigest()[:24]}{suffix}"
    try:
        data = _checked(path)
        if data is None:  # absent, or failed its check: built again
            _discard(path)
            data = _build(source, path)
        return NativeKernel(path, n, data)
    except (OSError, subprocess.SubprocessError, AttributeError, TypeError, ValueError,
            RuntimeError):  # llvmlite or the linker could not: numba's cache instead
        return None
