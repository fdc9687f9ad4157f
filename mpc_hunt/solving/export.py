"""A stage-form capture step (``rti``, ``stage-sqp``, a ``distributed`` robot's) as C sources for a robot's board
(``mpc-hunt export``).

For one problem's structure (controlled and held defenders, obstacles, horizon,
objective) the folder holds:

- ``capture_step.c``, ``capture_step.h``: the step CasADi generates (linearisation,
  HPIPM, read-back), with the rewrites of :mod:`mpc_hunt.solving.backends.hpipm_codegen`;
- ``mpc_hunt_step.c``, ``mpc_hunt_step.h``: ``mpc_hunt_step(theta, reference, plan, objective)``,
  the call a control loop makes: CasADi's calling convention wants argument and
  result pointer arrays longer than the inputs and outputs (it uses them as work
  space) and work vectors of the sizes ``capture_step_work`` gives; this wrapper
  holds them, allocated once, so the caller hands over plain arrays; for ``stage-sqp``
  it repeats the step at its own plan as :class:`~mpc_hunt.solving.step.CaptureStep` does;
- ``main.c``: reads states (θ and the reference) from standard input, prints their plans;
- ``Makefile``: ``make`` builds ``capture_step`` against HPIPM and BLASFEO (the
  stated dependencies; by default the copies CasADi's Python wheel ships, whose
  BLASFEO is its generic target: ``make BLASFEO=DIR`` links one built for the
  board's CPU, with the same version's headers);
- ``input.txt`` and ``expected.txt``: the problem's θ and reference, and Python's plan.

With the ``daqp-condensed`` backend (:mod:`mpc_hunt.solving.backends.daqp_condensed`, the ``distributed``
formulation's default) the step is condensed to a dense QP in its controls and solved by DAQP: the folder holds
CasADi's condensing (``capture_condense.c``, ``.h``), the step around DAQP (``mpc_hunt_step.c``: the C the
backend's own library is built from), DAQP's C sources (``daqp/``, MIT), ``main.c`` and a Makefile that needs
no library but libm, so ``make CC=aarch64-linux-gnu-gcc`` (or the target ``aarch64-linux``, which writes
that compiler into the Makefile) builds it for another CPU. The target ``cortex-m7`` writes, instead of ``main.c``,
a bare-metal program for a Cortex-M7 with a double-precision FPU (``board.c``, ``startup.c``, ``board.ld``: qemu's
mps2-an500 board) that steps input.txt's states compiled in and reports each step's SysTick count, the heap and
the stack over semihosting; ``make run`` runs it under ``qemu-system-arm -icount shift=0``.

HPIPM runs in the solver's ``mode`` (:data:`mpc_hunt.solving.backends.hpipm.MODES`): ``robust``, the
``hpipm`` backend's default, or ``balance``, which factorises by Cholesky instead of LQ, the path a BLASFEO
built for the CPU speeds up (its plans differ from ``robust``'s within HPIPM's
tolerances; Python's plan in ``expected.txt`` is solved in the same mode).

θ is :func:`mpc_hunt.formulations.capture_model.parameter_vector` followed by the field's
smoothing; the reference is the previous plan shifted one step (or every
defender held), as the formulation's ``step_inputs`` writes them.

Which step a backend's export writes is the backend's ``exports`` (``hpipm``, ``condensed``; None: no export). The
C, headers and Makefiles are templates (:mod:`mpc_hunt.solving.c_template`), filled in here.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mpc_hunt.capture.iteration import QPIteration
from mpc_hunt.capture.structure import Structure
from mpc_hunt.errors import SettingError
from mpc_hunt.solving.c_template import render
from mpc_hunt.solving.vendored_daqp import DAQP_SOURCES, DAQP_VERSION

NAME = "capture_step"

# The export's targets: the compiler the folder's Makefile builds with (None: make's own) and how to run it.
TARGETS: dict[str, dict[str, str | None]] = {
    "host": {"cc": None, "run": "./capture_step < input.txt", "install": ""},
    "aarch64-linux": {
        "cc": "aarch64-linux-gnu-gcc",
        "run": "qemu-aarch64 -L /usr/aarch64-linux-gnu ./capture_step < input.txt",
        "install": "apt-get install gcc-aarch64-linux-gnu",
    },
    "cortex-m7": {
        "cc": "arm-none-eabi-gcc",
        "run": "make run (qemu-system-arm -M mps2-an500)",
        "install": "apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi",
    },
}


def check_export(target: str, exports: str | None, iteration: QPIteration) -> None:
    """Refuse what the export cannot write, before any work: a target :func:`check_target` refuses, or a step of
    several QPs on a backend that ``exports`` the condensed step (a :class:`~mpc_hunt.errors.SettingError` naming
    ``target`` or ``backend``)."""
    check_target(target, exports)
    if exports == "condensed" and iteration.max_qps != 1:
        raise SettingError(
            "backend",
            "its export writes one QP a step (rti, distributed), not up to "
            f"{iteration.max_qps}; export this formulation with hpipm",
        )


def check_target(target: str, exports: str | None) -> None:
    """Refuse a target that is unknown, needs the solver built for it (the step a backend ``exports`` is not the
    condensed one, which carries its solver's sources), or whose compiler is missing (a
    :class:`~mpc_hunt.errors.SettingError` naming ``target``)."""
    import shutil

    if target not in TARGETS:
        raise SettingError("target", f"one of {', '.join(TARGETS)}, not {target!r}")
    cc = TARGETS[target]["cc"]
    if cc is None:
        return
    if exports != "condensed":
        raise SettingError(
            "target",
            "HPIPM and BLASFEO come built for this machine only (CasADi's wheel); export "
            "with backend daqp-condensed, whose solver's sources go with the step",
        )
    if shutil.which(cc) is None:
        raise SettingError("target", f"the cross compiler {cc} is not installed ({TARGETS[target]['install']})")


def numbers(values: np.ndarray) -> str:
    """``values`` one a line, each to the last bit (``input.txt``, ``expected.txt``)."""
    return "\n".join(f"{v:.17g}" for v in values) + "\n"


def generated(folder: Path, name: str, function) -> Path:
    """CasADi's C of ``function``, ``name``.c and its header, written into ``folder`` (made if need be); the .c."""
    import casadi as ca

    folder.mkdir(parents=True, exist_ok=True)
    generator = ca.CodeGenerator(f"{name}.c", {"with_header": True})
    generator.add(function)
    generator.generate(str(folder) + "/")
    return folder / f"{name}.c"


@dataclass(frozen=True)
class ExportedProblem:
    """The problem an export's folder carries: its structure, θ, the reference and Python's plan."""

    structure: Structure
    theta: np.ndarray
    reference: np.ndarray
    plan: np.ndarray

    def header(self, kind: str, **values) -> str:
        """``mpc_hunt_step.h`` of the ``kind`` of step (``hpipm``, ``condensed``): the structure's name, the lengths
        of θ, the reference and the plan, and the template's other ``values``."""
        return render(
            f"{kind}/mpc_hunt_step.h",
            structure=self.structure,
            n_theta=len(self.theta),
            n_reference=len(self.reference),
            n_plan=len(self.plan),
            **values,
        )

    def files(self) -> dict[str, str]:
        """``input.txt`` (θ, then the reference) and ``expected.txt`` (Python's plan)."""
        return {"input.txt": numbers(np.concatenate([self.theta, self.reference])), "expected.txt": numbers(self.plan)}


def written(folder: Path, files: dict[str, str]) -> list[Path]:
    """``files`` (name: text) written into ``folder``; their paths."""
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return [folder / name for name in files]


def write_condensed(folder: Path, step, problem: ExportedProblem, target: str = "host") -> list[Path]:
    """The folder of the module docstring for the ``daqp-condensed`` backend's step: CasADi's condensing
    (``capture_condense.c``), the step around DAQP (``mpc_hunt_step.c``, the C the backend's library is built
    from), DAQP's sources (``daqp/``), ``main.c``, a Makefile that needs nothing else, the input and Python's plan."""
    import shutil

    from mpc_hunt.solving.backends.condensed_compiled import NON_FINITE_INPUT, NON_FINITE_PLAN, step_source

    source = generated(folder, "capture_condense", step.function)
    daqp = folder / "daqp"
    for part in ("src", "include"):
        (daqp / part).mkdir(parents=True, exist_ok=True)
        for path in sorted((DAQP_SOURCES / part).glob("*.[ch]")):
            shutil.copyfile(path, daqp / part / path.name)
    shutil.copyfile(DAQP_SOURCES / "LICENSE", daqp / "LICENSE")
    cc = TARGETS[target]["cc"]
    files = {
        "mpc_hunt_step.h": problem.header(
            "condensed", non_finite_input=NON_FINITE_INPUT, non_finite_plan=NON_FINITE_PLAN
        ),
        "mpc_hunt_step.c": render("condensed/mpc_hunt_step.c", step=step_source(step.function, step.sizes)),
        "main.c": render("main.c"),
        "Makefile": render(
            "condensed/Makefile", structure=problem.structure, version=DAQP_VERSION, set_cc=f"CC = {cc}\n" if cc else ""
        ),
        **problem.files(),
    }
    if target == "cortex-m7":
        del files["main.c"]
        files.update(
            {
                "board.c": render("cortex-m7/board.c"),
                "startup.c": render("cortex-m7/startup.c"),
                "board.ld": render("cortex-m7/board.ld"),
                "Makefile": render("cortex-m7/Makefile", structure=problem.structure, version=DAQP_VERSION),
            }
        )
    return [source, source.with_suffix(".h"), *written(folder, files), daqp]


def write_step(
    folder: Path,
    step,
    exports: str | None,
    iteration: QPIteration,
    structure: Structure,
    theta: np.ndarray,
    reference: np.ndarray,
    plan: np.ndarray,
    target: str = "host",
) -> list[Path]:
    """Write the folder of the module docstring for the backend's ``step`` (the CasADi Function of a backend that
    ``exports`` the ``hpipm`` step, the condensed step of one that ``exports`` the ``condensed`` one) of
    ``structure``, repeated by ``iteration``'s rule, with the inputs ``theta``, ``reference`` and their plan, its
    Makefile building for ``target`` (:data:`TARGETS`); returns the files written.
    :meth:`mpc_hunt.solving.solver.CaptureSolver.export` calls it with the step it has set up."""
    check_export(target, exports, iteration)
    problem = ExportedProblem(structure, theta, reference, plan)
    if exports == "condensed":
        return write_condensed(folder, step, problem, target)
    from mpc_hunt.solving.backends.hpipm_codegen import patch
    from mpc_hunt.solving.compiled import casadi_paths

    source = generated(folder, NAME, step)
    source.write_text(patch(source.read_text(encoding="utf-8")), encoding="utf-8")
    iterations = dict(qps=iteration.max_qps, tolerance=repr(float(iteration.tolerance)))
    sizes = dict(sz_arg=step.sz_arg(), sz_res=step.sz_res(), sz_iw=step.sz_iw(), sz_w=step.sz_w(), name=step.name())
    files = {
        "mpc_hunt_step.h": problem.header("hpipm", **iterations),
        "mpc_hunt_step.c": render("hpipm/mpc_hunt_step.c", **sizes, **iterations),
        "main.c": render("main.c"),
        "Makefile": render("hpipm/Makefile", structure=structure, deps=casadi_paths()[1]),
        **problem.files(),
    }
    return [source, source.with_suffix(".h"), *written(folder, files)]
