"""Where a sweep's units run: ``local`` (a process pool on this machine) or ``ray`` (Ray tasks).

Both take (cell scenario, unit) pairs and hand back unit documents as the units finish, in whatever
order they finish; the sweep writes each one at once. Neither schedules anything itself beyond keeping a
bounded number of units in flight (twice the parallel slots), so an interrupt cancels little and memory
stays flat however large the sweep. ``ray`` connects to a running cluster (``ray.init(address=...)``, see
docs/sweeps.md) or starts a local Ray instance with ``--jobs`` CPUs, and shuts down only an instance it
started. Every node of a cluster needs the same ergosim installed: Ray sends the unit function by
reference.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import multiprocessing
import os
import signal
import socket
import sys
import time
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError, ErgosimError
from ergosim.experiment.interrupt import quiet_worker, signals_ignored, stop_pool
from ergosim.experiment.spawn_guard import check_main_guard
from ergosim.logs import configured_level
from ergosim.plugins import extension_modules
from ergosim.sweep.units import Unit, failed_document, run_unit

__all__ = ["Executor", "LocalExecutor", "RayExecutor", "SweepError", "make_executor", "EXECUTORS",
           "RAY_CONNECT_TIMEOUT"]

EXECUTORS = ("local", "ray")


class SweepError(ErgosimError):
    """The sweep cannot go on (a worker process died, the cluster went away); finished units are kept."""


Task = tuple[Any, Unit]


class Executor:
    """Context manager; :meth:`imap` yields unit documents as units finish. ``workers``: parallel slots."""

    name = "?"
    workers = 1

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, kind, err, tb) -> None:
        self.stop(cancel=kind is not None)

    def imap(self, tasks: Iterable[Task], actions: Sequence[str]) -> Iterator[dict[str, Any]]:
        """Run ``tasks``; yield each unit's document as it finishes (every executor defines it)."""
        raise NotImplementedError

    def stop(self, cancel: bool) -> None:
        """Release the workers; ``cancel``: drop queued units and kill running ones."""

    def describe(self) -> dict[str, Any]:
        return {"executor": self.name, "workers": self.workers}


class LocalExecutor(Executor):
    """``jobs`` processes (spawned, ignoring SIGINT/SIGTERM: the main process stops them); ``jobs`` 1 runs
    the units in this process."""

    name = "local"

    def __init__(self, jobs: int | None = None) -> None:
        self.workers = max(1, jobs or os.cpu_count() or 1)
        self._pool: cf.ProcessPoolExecutor | None = None

    def imap(self, tasks, actions):
        tasks = iter(tasks)
        if self.workers == 1:
            for scenario, unit in tasks:
                yield run_unit(scenario, unit, actions, extension_modules())
            return
        check_main_guard(where="jobs")
        ctx = multiprocessing.get_context("spawn")
        pending: dict[cf.Future, Unit] = {}
        extensions = extension_modules()

        def fill() -> None:
            for scenario, unit in tasks:
                pending[self._pool.submit(run_unit, scenario, unit, actions, extensions)] = unit
                if len(pending) >= 2 * self.workers:
                    break

        with signals_ignored():  # the workers start here and inherit SIG_IGN
            self._pool = cf.ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx,
                                                initializer=quiet_worker, initargs=(configured_level(),))
            fill()
        while pending:
            done, _ = cf.wait(pending, timeout=0.5, return_when=cf.FIRST_COMPLETED)
            for fut in done:
                unit = pending.pop(fut)
                try:
                    yield fut.result()
                except cf.process.BrokenProcessPool:
                    raise SweepError("a worker process died (out of memory, or killed); the finished "
                                     "units are kept: run the sweep again to resume",
                                     where="--executor local") from None
                except Exception as err:  # noqa: BLE001 - e.g. a unit that cannot be pickled back
                    yield failed_document(unit, f"{type(err).__name__}: {err}")
            fill()

    def stop(self, cancel: bool) -> None:
        if self._pool is None:
            return
        if cancel:
            stop_pool(self._pool)
        else:
            self._pool.shutdown()
        self._pool = None


def _import_roots(names: Sequence[str]) -> tuple[str, ...]:
    """The sys.path entries the driver imported the extension modules ``names`` from."""
    roots = []
    for name in names:
        file = getattr(sys.modules.get(name), "__file__", None)
        if file:
            path = Path(file).resolve()
            depth = name.count(".") + (1 if path.name == "__init__.py" else 0)
            roots.append(str(path.parents[depth]))
    return tuple(dict.fromkeys(roots))


def _ray_unit(scenario, unit: Unit, actions: Sequence[str], extensions: tuple[str, ...],
              roots: tuple[str, ...]) -> dict[str, Any]:
    """The Ray task: one unit. Ray workers share the terminal's process group, so a Ctrl-C meant for the
    driver must not fail the unit: the driver stops the workers itself. ``roots``: where the driver found
    the extension modules; a worker on the driver's machine imports them from there (on another node they
    must be installed, or the unit fails saying which module is missing)."""
    with contextlib.suppress(ValueError):  # not the main thread of the worker
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    for root in roots:
        if root not in sys.path and os.path.isdir(root):
            sys.path.append(root)
    return run_unit(scenario, unit, actions, extensions)


class RayExecutor(Executor):
    """Ray tasks of one CPU each on the cluster at ``address``, or on a local instance of ``jobs`` CPUs
    (all cores by default). A Ray already initialised in this process (e.g. by a test) is used as it is."""

    name = "ray"

    def __init__(self, jobs: int | None = None, address: str | None = None) -> None:
        try:
            import ray  # noqa: PLC0415 - an optional dependency
        except ImportError:
            raise ConfigError("Ray is not installed; install it with: pip install 'ergosim[ray]'",
                              where="--executor ray") from None
        self._ray = ray
        self._owned = False
        self.startup_s = 0.0
        if not ray.is_initialized():
            kwargs: dict[str, Any] = {"include_dashboard": False, "logging_level": logging.ERROR,
                                      "log_to_driver": False}
            if "OPENBLAS_CORETYPE" in os.environ:  # the cluster's workers run numpy on this BLAS kernel too
                kwargs["runtime_env"] = {"env_vars": {"OPENBLAS_CORETYPE": os.environ["OPENBLAS_CORETYPE"]}}
            if address:
                _reachable(address)
                kwargs["address"] = address
            else:
                kwargs["num_cpus"] = max(1, jobs or os.cpu_count() or 1)
            t0 = time.perf_counter()
            try:
                ray.init(**kwargs)
            except Exception as err:  # noqa: BLE001 - ray raises ConnectionError, RuntimeError, ValueError...
                what = f"cannot connect to the Ray cluster at {address}" if address else "cannot start Ray"
                raise ConfigError(f"{what}: {' '.join(str(err).split())[:300]}",
                                  where="--ray-address" if address else "--executor ray") from None
            self._owned = True
            self.startup_s = time.perf_counter() - t0
        cpus = int(ray.cluster_resources().get("CPU", 1))
        self.workers = max(1, min(jobs, cpus) if (jobs and address) else cpus)
        self._remote = ray.remote(num_cpus=1)(_ray_unit)
        self._pending: dict[Any, Unit] = {}
        self.address = address or ("local" if self._owned else "existing")

    def imap(self, tasks, actions):
        ray = self._ray
        tasks = iter(tasks)
        refs: dict[int, Any] = {}  # one object per cell scenario, shared by its units
        actions_ref = ray.put(list(actions))
        extensions = extension_modules()
        roots = _import_roots(extensions)
        pending = self._pending

        def fill() -> None:
            for scenario, unit in tasks:
                ref = refs.get(unit.cell)
                if ref is None:
                    ref = refs[unit.cell] = ray.put(scenario)
                pending[self._remote.remote(ref, unit, actions_ref, extensions, roots)] = unit
                if len(pending) >= 2 * self.workers:
                    break

        fill()
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=0.5)
            for ref in ready:
                unit = pending.pop(ref)
                try:
                    yield ray.get(ref)
                except ray.exceptions.RayError as err:  # a worker or node died under the unit
                    yield failed_document(unit, f"{type(err).__name__}: {' '.join(str(err).split())[:500]}")
            fill()

    def stop(self, cancel: bool) -> None:
        ray = self._ray
        if cancel:
            for ref in list(self._pending):
                with contextlib.suppress(Exception):
                    ray.cancel(ref, force=True)
        self._pending.clear()
        if self._owned and ray.is_initialized():
            ray.shutdown()
        self._owned = False

    def describe(self) -> dict[str, Any]:
        return {"executor": self.name, "workers": self.workers, "ray_address": self.address,
                "startup_s": self.startup_s}


RAY_CONNECT_TIMEOUT = 10.0
"""Seconds a Ray cluster's address has to accept a connection before the sweep is refused (Ray itself keeps
retrying an address where nothing listens for minutes)."""


def _reachable(address: str) -> None:
    """Refuse an address ``host:port`` (or ``ray://host:port``) where nothing accepts a connection within
    :data:`RAY_CONNECT_TIMEOUT`; ``auto`` and other forms are left to Ray."""
    host, sep, port = address.removeprefix("ray://").rpartition(":")
    if not sep or not port.isdigit() or not host:
        return
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=RAY_CONNECT_TIMEOUT):
            pass
    except OSError as err:
        why = "nothing answered" if isinstance(err, TimeoutError) else (err.strerror or str(err)).lower()
        raise ConfigError(f"cannot connect to the Ray cluster at {address}: {why} (within "
                          f"{RAY_CONNECT_TIMEOUT:g} s); is `ray start --head` running there?",
                          where="--ray-address") from None


def make_executor(kind: str, jobs: int | None = None, address: str | None = None) -> Executor:
    if kind == "local":
        if address:
            raise ConfigError("--ray-address needs --executor ray", where="--ray-address")
        return LocalExecutor(jobs)
    if kind == "ray":
        return RayExecutor(jobs, address)
    raise ConfigError(f"unknown executor {kind!r}; valid: {', '.join(EXECUTORS)}", where="--executor")
