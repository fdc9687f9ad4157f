"""The toolkit's own error types: raised for bad input instead of ``assert``."""


class MpcHuntError(Exception):
    """Base class of every error the toolkit raises on purpose."""


class ScenarioError(MpcHuntError, ValueError):
    """A scenario (or scenario file) is malformed; the message names the field."""


class DataFileError(MpcHuntError, ValueError):
    """A data file the toolkit reads (the learned attacker's weights, a problem set) is damaged; the message names
    the file."""


class SolverError(MpcHuntError):
    """A solve failed and the caller asked for an exception instead of a status."""


class SolverNotFoundError(MpcHuntError):
    """A backend's solver package is not installed; the message says how to install it."""


class BenchmarkError(MpcHuntError, ValueError):
    """A benchmark's input cannot be scored (an empty or negative sample, no problem selected)."""


class OptionError(MpcHuntError, ValueError):
    """A setting (an environment's argument, a controller's or a solver's option) is unknown or out of range; the
    message names it."""


class SettingError(OptionError):
    """A controller's settings are refused (:class:`mpc_hunt.control.spec.ControllerSpec`; a pair that cannot pose
    an objective, :func:`mpc_hunt.solving.registry.objective_refusal`): ``fields`` names them (``horizon``,
    ``time_limit``, ...), ``reason`` says why and how to fix it; each caller names them its own way (a flag, an
    argument)."""

    def __init__(self, fields: str | tuple[str, ...] | list[str], reason: str):
        self.fields = (fields,) if isinstance(fields, str) else tuple(fields)
        self.reason = reason
        super().__init__(f"{', '.join(self.fields)}: {reason}")

    def __reduce__(self):     # to pickle across processes (a sweep's workers)
        return type(self), (self.fields, self.reason)


class ActionError(MpcHuntError, ValueError):
    """An agent's action cannot be stepped with (not its space's shape, not finite numbers); the message names the
    agent."""


class SweepStopped(MpcHuntError):
    """A sweep could not go on (its workers kept dying, its cluster went away); its finished rows are kept."""


class WorkersDied(MpcHuntError):
    """Local worker processes kept dying (killed? out of memory?); what they finished was handed back."""


class UnknownNameError(MpcHuntError, KeyError):
    """A formulation, backend, controller or scenario name is not registered."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
