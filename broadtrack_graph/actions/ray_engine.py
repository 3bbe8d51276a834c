"""Ray as the engine of track-many: one Ray task per unit, on this machine or on a cluster.

Without an address Ray starts a private local instance with ``workers`` CPUs (one task per CPU)
bound to 127.0.0.1, no dashboard, and stops it at the end. With an address it joins that
cluster (``auto``: the cluster ``ray start`` started on this machine; ``HOST:PORT``: the head
node's GCS; ``ray://HOST:PORT``: the Ray Client server) and leaves it running. Workers on other
nodes need broadtrack-graph installed and the input and output paths on a shared file system.

Same interface as :class:`~broadtrack_graph.actions.parallel.SerialEngine`.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable

from broadtrack_graph.actions.parallel import one_line
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.prefetch import PREFETCH_ENV

logger = logging.getLogger(__name__)

INSTALL_HINT = ("track-many runs on Ray, which is not installed: pip install 'broadtrack-graph[scale]' "
                "(or pip install 'ray>=2.40,<3')")


LOOPBACK_ENV = {
    # Ray resolves 127.0.0.1 to this machine's network address (services.resolve_ip_for_localhost)
    # unless clusters are switched off: then a local instance binds to loopback only.
    "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0",
    "RAY_USAGE_STATS_ENABLED": "0",  # no usage report
}


def require_ray() -> None:
    """Raise an InputError saying in one line how to install Ray when it is not importable (nothing imported)."""
    import importlib.util

    if importlib.util.find_spec("ray") is None:
        raise InputError(None, INSTALL_HINT)


def import_ray(loopback: bool = False):
    """The ray module (InputError when missing); ``loopback``: set :data:`LOOPBACK_ENV` first.

    The loopback settings take effect only when ray is first imported in this process.
    """
    require_ray()
    if loopback:
        for key, value in LOOPBACK_ENV.items():
            os.environ.setdefault(key, value)
    import ray

    return ray


def prefetch_thread(prefetch: bool | None, workers: int, cores: int) -> bool:
    """Whether the units of a local instance decode in a background thread: as asked, else only when the
    workers leave a core idle for it (with every core busy the thread only competes with the other workers)."""
    return prefetch if prefetch is not None else workers < cores


class RayEngine:
    """Run calls as Ray tasks (one CPU each), retried ``retries`` times on an exception or a lost worker.

    Args:
        workers: CPUs of the local instance (default: this machine's cores); ignored with an address.
        address: None for a private local instance, else the cluster to join.
        retries: extra attempts per task.
        prefetch: local instance only: whether a unit decodes its frames in a background thread
            (:mod:`broadtrack_graph.io.prefetch`). None (default): only when the workers leave a core
            idle for it; False: never (each unit on exactly its one CPU, as when measuring scaling).
    """

    name = "ray"

    def __init__(self, workers: int | None = None, address: str | None = None, retries: int = 2,
                 prefetch: bool | None = None) -> None:
        self.address = address
        self.workers = int(workers or os.cpu_count() or 1)
        self.retries = max(0, int(retries))
        self.prefetch = prefetch
        self._ray = None

    def __enter__(self) -> "RayEngine":
        ray = import_ray(loopback=self.address is None)
        if ray.is_initialized():
            ray.shutdown()
        kwargs = {"include_dashboard": False, "log_to_driver": False, "configure_logging": True,
                  "logging_level": logging.WARNING}
        if self.address is None:
            if not prefetch_thread(self.prefetch, self.workers, os.cpu_count() or 1):
                kwargs["runtime_env"] = {"env_vars": {PREFETCH_ENV: "0"}}
            ray.init(address="local", num_cpus=self.workers, **kwargs)
        else:
            try:
                ray.init(address=self.address, **({} if self.address.startswith("ray://") else kwargs))
            except (ConnectionError, RuntimeError, ValueError) as exc:
                raise InputError(None, f"cannot join the Ray cluster at {self.address}: {one_line(exc)}") from None
            self.workers = int(ray.cluster_resources().get("CPU", 1))
        self._ray = ray
        logger.info("Ray %s: %d CPUs (%s)", ray.__version__, self.workers, self.address or "local")
        return self

    def __exit__(self, *exc) -> None:
        if self._ray is not None:
            self._ray.shutdown()
            self._ray = None

    def nodes(self) -> list[str]:
        """Addresses of the nodes alive in the cluster."""
        return [node.get("NodeManagerAddress") for node in self._ray.nodes() if node.get("Alive")]

    def run(self, function: Callable, calls: list[tuple[object, tuple]], on_done: Callable, on_error: Callable) -> None:
        """Submit every call at once (Ray queues them on free CPUs) and report each as it finishes."""
        ray = self._ray
        remote = ray.remote(num_cpus=1, max_retries=self.retries, retry_exceptions=True)(function)
        pending = {remote.remote(*args): key for key, args in calls}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                key = pending.pop(ref)
                try:
                    result = ray.get(ref)
                except Exception as exc:  # noqa: BLE001 -- reported per unit, the others go on
                    cause = getattr(exc, "cause", None)
                    on_error(key, one_line(cause if isinstance(cause, BaseException) else exc))
                    continue
                on_done(key, result)
