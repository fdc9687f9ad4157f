"""The toolkit's own error types: raised for bad input instead of ``assert``."""


class MpcHuntError(Exception):
    """Base class of every error the toolkit raises on purpose."""


class ScenarioError(MpcHuntError, ValueError):
    """A scenario (or scenario file) is malformed; the message names the field."""


class SolverError(MpcHuntError):
    """A solve failed and the caller asked for an exception instead of a status."""


class UnknownNameError(MpcHuntError, KeyError):
    """A formulation, backend or scenario name is not registered."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
