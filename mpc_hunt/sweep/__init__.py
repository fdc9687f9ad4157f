"""Random hunts at scale: random scenarios, reachability, the sweep on local processes or Dask, its results file,
the failure taxonomy, the summary, and two strategies told apart on the same hunts."""

from mpc_hunt.sweep.paired import versus, versus_table
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.sweep.runner import Hunt, connect_dask, run_dask, run_hunt, run_local
from mpc_hunt.sweep.store import SweepStore
from mpc_hunt.sweep.summary import summarise

__all__ = [
    "Hunt",
    "ScenarioRanges",
    "SweepStore",
    "connect_dask",
    "run_dask",
    "run_hunt",
    "run_local",
    "summarise",
    "sweep_scenario",
    "versus",
    "versus_table",
]
