"""A sweep's hunts run into its results file, each row stored as its hunt finishes, until all are done, Ctrl-C, or
the workers or the cluster are lost (``mpc-hunt sweep`` and the sweep study run it)."""

from __future__ import annotations

from typing import Callable, Iterable

from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sweep.runner import Hunt, run_dask, run_local
from mpc_hunt.sweep.store import SweepStore


def run_into(
    store: SweepStore,
    todo: Iterable[Hunt],
    workers: int | None = None,
    client=None,
    update: Callable[[int], None] | None = None,
) -> str | None:
    """Run ``todo`` on ``workers`` local processes, or on the Dask cluster of ``client``, into ``store``;
    ``update(finished)`` after each hunt. None when every hunt finished, else why it stopped (``interrupted``,
    ``error: …``): the finished hunts are in ``store``, and a resumed sweep runs the rest."""
    rows = run_dask(todo, client) if client else run_local(todo, workers)
    try:
        for finished, row in enumerate(rows, 1):
            store.add(row)
            if update:
                update(finished)
    except KeyboardInterrupt:
        rows.close()
        return "interrupted"
    except MpcHuntError as exc:  # workers or the cluster lost, a scenario that cannot be drawn
        return f"error: {exc}"
    return None
