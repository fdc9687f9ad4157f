"""The toolkit's own error types: raised for bad input instead of ``assert``.

An error about a function's argument names it, as the function does (``resume``, ``time_limit``), marked with
:func:`field_name`: its message shows the name as it is, and :meth:`MpcHuntError.named` as a caller names it (the
command line, its flag: ``--resume``).
"""

from __future__ import annotations

import re
from typing import Callable

_MARK = "\x1f"  # around a field's name in a message (ASCII's unit separator)
_FIELD = re.compile(f"{_MARK}(\\w+){_MARK}")


def field_name(name: str) -> str:
    """The argument or setting ``name``, marked for a message: shown as it is, or as a caller names it."""
    return f"{_MARK}{name}{_MARK}"


def _shown(text: str, name: Callable[[str], str]) -> str:
    """``text`` with each field marked in it shown as ``name(field)``."""
    return _FIELD.sub(lambda match: name(match[1]), text)


class MpcHuntError(Exception):
    """Base class of every error the toolkit raises on purpose."""

    def named(self, name: Callable[[str], str]) -> str:
        """The message, each field in it (:func:`field_name`) shown as ``name(field)``: a command line's flag."""
        return _shown(Exception.__str__(self), name)

    def __str__(self) -> str:
        return self.named(str)


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
    """Arguments or settings are refused (a :class:`mpc_hunt.control.spec.ControllerSpec`'s; a pair that cannot pose
    an objective, :func:`mpc_hunt.solving.registry.objective_refusal`; a sweep's results file's, ...): ``fields``
    names them (``horizon``, ``resume``, ...), ``reason`` says why and how to fix it, any other field in it marked
    (:func:`field_name`); the message is ``fields: reason``, each caller naming the fields its own way
    (:meth:`named`)."""

    def __init__(self, fields: str | tuple[str, ...] | list[str], reason: str):
        self.fields = (fields,) if isinstance(fields, str) else tuple(fields)
        self._reason = reason
        super().__init__(f"{', '.join(map(field_name, self.fields))}: {reason}")

    @property
    def reason(self) -> str:
        """Why, its fields as they are."""
        return _shown(self._reason, str)

    def __reduce__(self):  # to pickle across processes (a sweep's workers)
        return type(self), (self.fields, self._reason)


class ActionError(MpcHuntError, ValueError):
    """An agent's action cannot be stepped with (not its space's shape, not finite numbers); the message names the
    agent."""


class SweepStopped(MpcHuntError):
    """A sweep could not go on (its workers kept dying, its cluster went away); its finished rows are kept."""


class WorkersDied(MpcHuntError):
    """Local worker processes kept dying (killed? out of memory?); what they finished was handed back."""


class UnknownNameError(MpcHuntError, KeyError):
    """A formulation, backend, controller or scenario name is not registered (its message not quoted, as
    KeyError's would be: :meth:`MpcHuntError.__str__` comes first)."""
