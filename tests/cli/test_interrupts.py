"""Ctrl-C reaches compiled loops.

The fast path's RK4 loop runs in compiled slices that return to Python, so a SIGINT that
lands inside it raises KeyboardInterrupt within a slice; slicing changes no bit of the
result.  Every child process is started in its own session and killed (its whole process
group) when the test ends, whatever happened.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("numba")

from gfrf.model.equation import parse_model
from gfrf.model.signals import parse_input
from gfrf.sim import fastsim
from gfrf.sim.system import build_system

ROOT = Path(__file__).resolve().parents[2]
DUFFING = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"
#: Seconds between the signal and KeyboardInterrupt (a slice is a few ms of CPU).
LATENCY = 1.0


@pytest.fixture
def spawn() -> Iterator[Callable[..., subprocess.Popen]]:
    """Popen in a new session; every process group started is killed at teardown."""
    started: list[subprocess.Popen] = []

    def start(argv: list[str], **kwargs: object) -> subprocess.Popen:
        proc = subprocess.Popen(argv, start_new_session=True, **kwargs)  # type: ignore[call-overload]
        started.append(proc)
        return proc

    yield start
    for proc in started:
        if proc.poll() is None:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait()


def _fast(system: object, text: str, t_end: float, dt: float, blowup: float = 1e6) -> object:
    signal_ = parse_input(text)
    t_eval = np.linspace(0.0, t_end, 401)
    return fastsim.simulate_fast(system, signal_, np.zeros(2), t_end, t_eval, blowup=blowup,
                                 dt=dt, rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("blowup", [1e6, 0.25])  # the second stops inside a slice
def test_sliced_loop_is_bit_identical_to_one_call(monkeypatch: pytest.MonkeyPatch,
                                                  blowup: float) -> None:
    system = build_system(parse_model(DUFFING))
    text, t_end, dt = "0.1*sin(t) + 0.2*step(t-1.3) + 0.05*abs(sin(3*t))", 20.0, 1e-3
    monkeypatch.setattr(fastsim, "SLICE", 2**62)
    whole = _fast(system, text, t_end, dt, blowup)
    monkeypatch.setattr(fastsim, "SLICE", 7)
    calls = []
    module, _ = fastsim.compile_system(system)
    real = module.rk4

    class Spy:
        def __getattr__(self, name: str) -> object:
            return getattr(module, name)

        def rk4(self, *args: object) -> int:
            calls.append(args[-3:-1])
            return real(*args)

    monkeypatch.setattr(fastsim, "compile_system", lambda _: (Spy(), 0.0))
    sliced = _fast(system, text, t_end, dt, blowup)
    assert len(calls) > 50
    assert whole.status == sliced.status and whole.message == sliced.message
    assert whole.blowup_time == sliced.blowup_time
    for a, b in ((whole.t, sliced.t), (whole.states, sliced.states), (whole.u, sliced.u)):
        assert a.shape == b.shape and np.array_equal(a, b)
    assert whole.status == ("blowup" if blowup < 1 else "ok")


def test_ctrl_c_inside_the_compiled_loop_stops_it_at_once(monkeypatch: pytest.MonkeyPatch,
                                                          spawn: Callable[..., subprocess.Popen]
                                                          ) -> None:
    """SIGINT from another process (a thread of this one could not run: numba holds the
    GIL inside the loop) 0.3 s into the loop; KeyboardInterrupt within :data:`LATENCY`."""
    system = build_system(parse_model(DUFFING))
    module, _ = fastsim.compile_system(system)
    killers: list[subprocess.Popen] = []
    sender = f"sleep 0.3; date +%s.%N; kill -INT {os.getpid()}"

    class Spy:
        """The module; its first loop call starts the process that sends the signal."""

        def __getattr__(self, name: str) -> object:
            return getattr(module, name)

        def rk4(self, *args: object) -> int:
            if not killers:
                killers.append(spawn(["sh", "-c", sender], stdout=subprocess.PIPE))
            return module.rk4(*args)

    monkeypatch.setattr(fastsim, "compile_system", lambda _: (Spy(), 0.0))
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            # 2e7 steps: seconds of loop (the old code ran it to the end, then failed
            # with a SystemError out of numba's result boxing)
            _fast(system, "0.1*sin(t)", 2e4, 1e-3)
        caught = time.time()
    finally:
        signal.signal(signal.SIGINT, previous)
    sent = float(killers[0].communicate(timeout=30)[0])
    assert caught - sent < LATENCY


def test_ctrl_c_inside_the_loop_exits_130(spawn: Callable[..., subprocess.Popen],
                                          tmp_path: Path) -> None:
    """The CLI, warm cache, SIGINT to the process group once the loop has started."""
    script = f"""
import signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)  # as under a terminal
from gfrf.sim import fastsim
compile_system = fastsim.compile_system
def spying(system):
    module, seconds = compile_system(system)
    class Spy:
        def __getattr__(self, name):
            return getattr(module, name)
        def rk4(self, *args):
            print("loop", flush=True)
            return module.rk4(*args)
    return Spy(), seconds
fastsim.compile_system = spying
from gfrf.cli import main
sys.exit(main(["simulate", {str(ROOT / "models" / "duffing.toml")!r}, "--input",
               "0.1*sin(t)", "--t-end", "1.5e4", "--dt", "1e-3", "--method", "fast",
               "--csv", {str(tmp_path / "trace.csv")!r}]))
"""
    proc = spawn([sys.executable, "-c", script], stdout=subprocess.PIPE,
                 stderr=subprocess.PIPE, cwd=ROOT)
    assert proc.stdout.readline() == b"loop\n"  # the compiled loop is running
    os.killpg(proc.pid, signal.SIGINT)
    start = time.perf_counter()
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert err.decode() == "gfrf: interrupted\n"
    assert time.perf_counter() - start < 5.0
    assert not (tmp_path / "trace.csv").exists()
