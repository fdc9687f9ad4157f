"""A stage-form capture step (``rti``, ``stage-sqp``, a ``distributed`` robot's) as C sources for a robot's board (``mpc-hunt export``).

For one problem's structure (controlled and held defenders, obstacles, horizon,
objective) the folder holds:

- ``capture_step.c``, ``capture_step.h``: the step CasADi generates (linearisation,
  HPIPM, read-back), with the rewrites of :mod:`mpc_hunt.solving.backends.hpipm_codegen`;
- ``mpc_hunt_step.c``, ``mpc_hunt_step.h``: ``mpc_hunt_step(theta, reference, plan, objective)``,
  the call a control loop makes: CasADi's calling convention wants argument and
  result pointer arrays longer than the inputs and outputs (it uses them as work
  space) and work vectors of the sizes ``capture_step_work`` gives; this wrapper
  holds them, allocated once, so the caller hands over plain arrays; for ``stage-sqp``
  it repeats the step at its own plan as :class:`~mpc_hunt.solving.loop.CaptureLoop` does;
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
no library but libm, so ``make CC=aarch64-linux-gnu-gcc`` (or ``export --target aarch64-linux``, which writes
that compiler into the Makefile) builds it for another CPU. ``--target cortex-m7`` writes, instead of ``main.c``,
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
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mpc_hunt.capture.iteration import QPIteration
from mpc_hunt.capture.structure import Structure
from mpc_hunt.errors import MpcHuntError

NAME = "capture_step"

WRAPPER_H = """\
/* The capture step of mpc-hunt, structure {structure}: one call per control step. */
#ifndef MPC_HUNT_STEP_H
#define MPC_HUNT_STEP_H
#define MPC_HUNT_THETA {n_theta}        /* θ: the parameter vector, then the field's smoothing */
#define MPC_HUNT_REFERENCE {n_reference}    /* the reference plan, steps 1..N, defenders in order, (x, y) */
#define MPC_HUNT_PLAN {n_plan}         /* the plan, laid out as the reference */
/* At most {qps} QP(s) a step, each linearised at the last one's plan, until no position moves by
   more than {tolerance!r} m. Returns 0 solved; HPIPM's status of a failed QP: 1 iteration limit, 2 minimum step,
   3 NaN; 4 no convergence in {qps} QPs; -1 the call failed. After a failed QP ``plan`` holds the last usable plan
   of the step (the reference, if none). ``objective`` may be NULL. Not reentrant: one control loop per process. */
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective);
#endif
"""

WRAPPER_C = """\
#include <math.h>
#include "capture_step.h"
#include "mpc_hunt_step.h"

int mpc_hunt_hpipm_status(void);

int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective) {{
  static const casadi_real *arg[{sz_arg}];
  static casadi_real *res[{sz_res}];
  static casadi_int iw[{sz_iw} + 1];
  static casadi_real w[{sz_w} + 1];
  static double start[MPC_HUNT_PLAN];           /* where the QP is linearised: the reference, then each plan */
  int i, k, status;
  double move;
  for (i = 0; i < MPC_HUNT_PLAN; ++i) start[i] = reference[i];
  arg[0] = theta; arg[1] = start; arg[2] = 0; arg[3] = 0;     /* no starting duals */
  res[0] = plan; res[1] = objective; res[2] = 0; res[3] = 0; res[4] = 0;
  for (k = 0; k < {qps}; ++k) {{
    if ({name}(arg, res, iw, w, 0)) return -1;
    status = mpc_hunt_hpipm_status();
    for (i = 0; i < MPC_HUNT_PLAN && status == 0; ++i) if (!isfinite(plan[i])) status = 3;
    if (status != 0) {{
      for (i = 0; i < MPC_HUNT_PLAN; ++i) plan[i] = start[i];
      return status;
    }}
    if ({qps} == 1) return 0;
    move = 0;
    for (i = 0; i < MPC_HUNT_PLAN; ++i) if (fabs(plan[i] - start[i]) > move) move = fabs(plan[i] - start[i]);
    if (move <= {tolerance!r}) return 0;
    for (i = 0; i < MPC_HUNT_PLAN; ++i) start[i] = plan[i];
  }}
  return 4;
}}
"""

MAIN_C = """\
/* Reads states (MPC_HUNT_THETA then MPC_HUNT_REFERENCE numbers each, separated by white space) from standard
   input until its end and prints each plan, one number a line. With --time, also each step's wall time in
   microseconds on stderr. Malformed input (a token that is not a finite number, a state cut short) is one line
   on stderr and exit status 2, before any plan of that state. */
#define _POSIX_C_SOURCE 199309L
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "mpc_hunt_step.h"

#define TOKEN 64

/* The next token of standard input into token: 1, 0 at the end of the input, -1 when it is too long. */
static int next_token(char *token) {
  int c, n = 0;
  do c = getchar(); while (c != EOF && isspace(c));
  if (c == EOF) return 0;
  for (; c != EOF && !isspace(c); c = getchar()) {
    if (n == TOKEN - 1) return -1;
    token[n++] = (char) c;
  }
  token[n] = 0;
  return 1;
}

static int read_numbers(double *x, int n, const char *what, int state) {
  char token[TOKEN], *end;
  int i, got;
  for (i = 0; i < n; ++i) {
    got = next_token(token);
    if (got == 0) {
      if (i == 0 && !strcmp(what, "theta")) return 0;           /* the end of the input */
      fprintf(stderr, "input: state %d: %s[%d] missing (a state is %d numbers)\\n", state, what, i,
              MPC_HUNT_THETA + MPC_HUNT_REFERENCE);
      return -1;
    }
    if (got < 0) {
      fprintf(stderr, "input: state %d: %s[%d]: a token longer than %d characters\\n", state, what, i, TOKEN - 1);
      return -1;
    }
    x[i] = strtod(token, &end);
    if (end == token || *end) {
      fprintf(stderr, "input: state %d: %s[%d]: '%s' is not a number\\n", state, what, i, token);
      return -1;
    }
    if (!isfinite(x[i])) {
      fprintf(stderr, "input: state %d: %s[%d]: '%s' is not finite\\n", state, what, i, token);
      return -1;
    }
  }
  return 1;
}

int main(int argc, char **argv) {
  static double theta[MPC_HUNT_THETA], reference[MPC_HUNT_REFERENCE], plan[MPC_HUNT_PLAN];
  int i, read, status, state = 0, failed = 0, timed = argc > 1 && !strcmp(argv[1], "--time");
  struct timespec start, end;
  while ((read = read_numbers(theta, MPC_HUNT_THETA, "theta", state)) == 1) {
    if (read_numbers(reference, MPC_HUNT_REFERENCE, "reference", state) != 1) return 2;
    clock_gettime(CLOCK_MONOTONIC, &start);
    status = mpc_hunt_step(theta, reference, plan, 0);
    clock_gettime(CLOCK_MONOTONIC, &end);
    if (timed) fprintf(stderr, "time_us %.3f\\n", (end.tv_sec - start.tv_sec) * 1e6 + (end.tv_nsec - start.tv_nsec) * 1e-3);
    for (i = 0; i < MPC_HUNT_PLAN; ++i) printf("%.17g\\n", plan[i]);
    if (status != 0) { fprintf(stderr, "state %d: step status %d\\n", state, status); failed = 1; }
    ++state;
  }
  if (read < 0) return 2;
  if (state == 0) { fprintf(stderr, "input: no state\\n"); return 2; }
  return failed;
}
"""

MAKEFILE = """\
# The capture step of mpc-hunt, structure {structure}.
# Needs HPIPM and BLASFEO (headers and libraries); by default the copies in CasADi's Python wheel.
DEPS ?= {deps}
# A BLASFEO built for the target CPU (same version as HPIPM's): make BLASFEO=/path/to/its/lib
BLASFEO ?= $(DEPS)
CC ?= gcc
CFLAGS ?= -O2
# BLASFEO linked first and kept, so that HPIPM's own dependency on it resolves to that one.
LDLIBS = -Wl,--no-as-needed -lblasfeo -Wl,--as-needed -lhpipm -lm

capture_step: main.o mpc_hunt_step.o capture_step.o
\t$(CC) $(CFLAGS) -o $@ $^ -L$(BLASFEO) -L$(DEPS) $(LDLIBS) -Wl,-rpath,$(BLASFEO) -Wl,-rpath,$(DEPS)

%.o: %.c capture_step.h mpc_hunt_step.h
\t$(CC) $(CFLAGS) -I$(DEPS)/include -c $<

clean:
\trm -f capture_step *.o
"""


DAQP_H = """\
/* The capture step of mpc-hunt, structure {structure}, condensed and solved by DAQP: one call per control step. */
#ifndef MPC_HUNT_STEP_H
#define MPC_HUNT_STEP_H
#define MPC_HUNT_THETA {n_theta}        /* θ: the parameter vector, then the field's smoothing */
#define MPC_HUNT_REFERENCE {n_reference}    /* the reference plan, steps 1..N, defenders in order, (x, y) */
#define MPC_HUNT_PLAN {n_plan}         /* the plan, laid out as the reference */
/* Returns 0 solved; DAQP's exit flag of a failed QP (-1 infeasible, -2 cycling, -3 unbounded, -4 iteration
   limit, ...); {non_finite_input} a non-finite input or QP, {non_finite_plan} a non-finite plan, -99 no memory.
   A failed step leaves the reference in ``plan``. Each step starts from the last one's working set (a failed
   warm start is retried cold). ``objective`` may be NULL. Not reentrant: one control loop per process (for
   more, mpc_hunt_daqp_new and mpc_hunt_daqp_solve in mpc_hunt_step.c). */
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective);
#endif
"""

DAQP_STEP = """\
#include "capture_condense.h"
#include "mpc_hunt_step.h"
{step}
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective) {{
  static mpc_hunt_daqp *s = 0;
  int i;
  if (!s && !(s = mpc_hunt_daqp_new())) {{
    for (i = 0; i < MPC_HUNT_PLAN; ++i) plan[i] = reference[i];
    return -99;
  }}
  return mpc_hunt_daqp_solve(s, theta, reference, plan, objective);
}}
"""

DAQP_MAKEFILE = """\
# The capture step of mpc-hunt, structure {structure}: condensed, solved by DAQP {version} (its C sources in
# daqp/, MIT licence), nothing else needed. For another CPU: make CC=<its cross compiler> (clean first).
{cc}CFLAGS ?= -O2
DAQP = daqp
OBJECTS = main.o mpc_hunt_step.o capture_condense.o $(patsubst %.c,%.o,$(wildcard $(DAQP)/src/*.c))

capture_step: $(OBJECTS)
\t$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ -lm

%.o: %.c capture_condense.h mpc_hunt_step.h
\t$(CC) $(CFLAGS) -I$(DAQP)/include -c $< -o $@

clean:
\trm -f capture_step $(OBJECTS)
"""

# A Cortex-M7 without an operating system (``--target cortex-m7``): the start-up, the memory map of qemu's
# mps2-an500 board, and a main that steps the states of input.txt (compiled in) and reports on semihosting.
BOARD_STARTUP = r"""/* Cortex-M7 start-up for a bare-metal capture step: the vector table, .data and .bss, the FPU on, main. */
#include <stdint.h>
#include <stdlib.h>

extern uint32_t __stack_top, __data_load, __data_start, __data_end, __bss_start, __bss_end;
extern int main(void);
extern void initialise_monitor_handles(void);

void Reset_Handler(void) {
  uint32_t *src = &__data_load, *dst = &__data_start;
  while (dst < &__data_end) *dst++ = *src++;
  for (dst = &__bss_start; dst < &__bss_end;) *dst++ = 0;
  *(volatile uint32_t *) 0xE000ED88 |= 0xFu << 20;          /* CPACR: CP10 and CP11, the FPU, full access */
  __asm volatile ("dsb\n isb");
  initialise_monitor_handles();                             /* semihosting: stdout, stderr, exit */
  exit(main());
}

static void Fault_Handler(void) { exit(3); }

__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
  &__stack_top, (void *) Reset_Handler, (void *) Fault_Handler, (void *) Fault_Handler, (void *) Fault_Handler,
  (void *) Fault_Handler, (void *) Fault_Handler};
"""

BOARD_LD = r"""/* mps2-an500 (Cortex-M7): code in ZBT SSRAM1 (as flash), data, heap and stack in ZBT SSRAM2&3. */
MEMORY {
  FLASH (rx) : ORIGIN = 0x00000000, LENGTH = 4M
  RAM (rwx) : ORIGIN = 0x20000000, LENGTH = 4M
}
ENTRY(Reset_Handler)
SECTIONS {
  .text : { KEEP(*(.vectors)) *(.text*) *(.rodata*) . = ALIGN(8); } > FLASH
  .ARM.exidx : { *(.ARM.exidx*) } > FLASH
  .data : { __data_start = .; *(.data*) . = ALIGN(8); __data_end = .; } > RAM AT > FLASH
  __data_load = LOADADDR(.data);
  .bss (NOLOAD) : { __bss_start = .; *(.bss*) *(COMMON) . = ALIGN(8); __bss_end = .; } > RAM
  end = .;                                                  /* the heap from here (newlib's sbrk) */
  __stack_top = ORIGIN(RAM) + LENGTH(RAM);
}
"""

BOARD_MAIN = r"""/* The capture step on a bare-metal Cortex-M7 (qemu-system-arm -M mps2-an500 -icount shift=0 -semihosting):
   every state of input.txt (compiled in) stepped in turn, each plan printed; on stderr each step's SysTick count
   (the CPU clock; under -icount shift=0 one instruction is 1 ns of the board's 25 MHz, 40 instructions a tick),
   a calibration loop of known length, the heap in use and the stack's high-water mark. */
#include <malloc.h>
#include <stdint.h>
#include <stdio.h>
#include "mpc_hunt_step.h"
#include "board_input.h"

#define SYST_CSR (*(volatile uint32_t *) 0xE000E010)
#define SYST_RVR (*(volatile uint32_t *) 0xE000E014)
#define SYST_CVR (*(volatile uint32_t *) 0xE000E018)
#define STATE (MPC_HUNT_THETA + MPC_HUNT_REFERENCE)
#define PAINT 0xA5A5A5A5u

extern uint32_t end, __stack_top;

static uint32_t ticks(uint32_t start) { return (start - SYST_CVR) & 0xFFFFFFu; }   /* SysTick counts down */

static void __attribute__((noinline)) spin(uint32_t n) {    /* 2 instructions an iteration: subs, bne */
  __asm volatile ("1: subs %0, %0, #1\n bne 1b" : "+r"(n));
}

int main(void) {
  static double plan[MPC_HUNT_PLAN];
  volatile uint32_t *p;
  uint32_t start, *sp, lowest;
  int s, i, status, failed = 0;
  __asm volatile ("mov %0, sp" : "=r"(sp));
  for (p = sp - 64 * 1024 / 4; p < sp - 16; ++p) *p = PAINT;      /* 64 KiB of stack below this frame */
  SYST_RVR = 0xFFFFFF; SYST_CVR = 0; SYST_CSR = 5;               /* the CPU clock, no interrupt */
  start = SYST_CVR; spin(1000000); fprintf(stderr, "calibration 2000000 %lu\n", (unsigned long) ticks(start));
  for (s = 0; s < (int) (sizeof board_input / sizeof board_input[0]) / STATE; ++s) {
    start = SYST_CVR;
    status = mpc_hunt_step(board_input + s * STATE, board_input + s * STATE + MPC_HUNT_THETA, plan, 0);
    fprintf(stderr, "ticks %lu\n", (unsigned long) ticks(start));
    for (i = 0; i < MPC_HUNT_PLAN; ++i) printf("%.17g\n", plan[i]);
    if (status) { fprintf(stderr, "state %d: step status %d\n", s, status); failed = 1; }
  }
  for (p = sp - 64 * 1024 / 4; p < sp - 16 && *p == PAINT; ++p) ;
  lowest = (uint32_t) p;
  fprintf(stderr, "heap %d\nstack %lu\n", mallinfo().uordblks, (unsigned long) ((uint32_t) &__stack_top - lowest));
  return failed;
}
"""

BOARD_MAKEFILE = r"""# The capture step of mpc-hunt, structure @STRUCTURE@: condensed, solved by DAQP @VERSION@ (its C sources in
# daqp/, MIT licence), for a Cortex-M7 with a double-precision FPU and no operating system; input.txt's states are
# compiled in (board_input.h). `make run` runs it on qemu's mps2-an500 board: plans on stdout; on stderr each
# step's SysTick count (under -icount shift=0, 40 instructions a tick: see the calibration line), the heap in use
# and the stack's high-water mark. Needs arm-none-eabi-gcc with newlib (semihosting: rdimon.specs).
CC = arm-none-eabi-gcc
CPU ?= -mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb
CFLAGS ?= -O2
DAQP = daqp
OBJECTS = board.o startup.o mpc_hunt_step.o capture_condense.o $(patsubst %.c,%.o,$(wildcard $(DAQP)/src/*.c))
QEMU = qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none -icount shift=0 \
	-semihosting-config enable=on,target=native

capture_step.elf: $(OBJECTS) board.ld
	$(CC) $(CPU) $(CFLAGS) -nostartfiles --specs=rdimon.specs -T board.ld -Wl,--gc-sections -o $@ $(OBJECTS) -lm

%.o: %.c capture_condense.h mpc_hunt_step.h
	$(CC) $(CPU) $(CFLAGS) -ffunction-sections -fdata-sections -I$(DAQP)/include -c $< -o $@

board.o: board_input.h

board_input.h: input.txt
	awk 'BEGIN { print "static const double board_input[] = {" } { for (i = 1; i <= NF; ++i) print $$i "," } \
	END { print "};" }' input.txt > $@

run: capture_step.elf
	$(QEMU) -kernel capture_step.elf

clean:
	rm -f capture_step.elf board_input.h $(OBJECTS)
"""


# The export's targets: the compiler the folder's Makefile builds with (None: make's own) and how to run it.
TARGETS = {
    "host": {"cc": None, "run": "./capture_step < input.txt", "install": ""},
    "aarch64-linux": {"cc": "aarch64-linux-gnu-gcc", "run": "qemu-aarch64 -L /usr/aarch64-linux-gnu ./capture_step "
                      "< input.txt", "install": "apt-get install gcc-aarch64-linux-gnu"},
    "cortex-m7": {"cc": "arm-none-eabi-gcc", "run": "make run (qemu-system-arm -M mps2-an500)",
                  "install": "apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi"},
}


def check_export(target: str, condensed: bool, iteration: QPIteration) -> None:
    """Refuse what the export cannot write, before any work: a target :func:`check_target` refuses, or a step of
    several QPs on the condensed backend."""
    check_target(target, condensed)
    if condensed and iteration.max_qps != 1:
        raise MpcHuntError("backend daqp-condensed: its export writes one QP a step (rti, distributed), not "
                           f"up to {iteration.max_qps}; export this formulation with hpipm")


def check_target(target: str, condensed: bool) -> None:
    """Refuse a target that is unknown, needs a backend's solver built for it, or whose compiler is missing."""
    import shutil

    if target not in TARGETS:
        raise MpcHuntError(f"--target: one of {', '.join(TARGETS)}, not {target!r}")
    cc = TARGETS[target]["cc"]
    if cc is None:
        return
    if not condensed:
        raise MpcHuntError(f"--target {target}: HPIPM and BLASFEO come built for this machine only (CasADi's "
                           "wheel); export with --backend daqp-condensed, whose solver's sources go with the step")
    if shutil.which(cc) is None:
        raise MpcHuntError(f"--target {target}: the cross compiler {cc} is not installed "
                           f"({TARGETS[target]['install']})")


def write_condensed(folder: Path, step, structure: Structure, theta: np.ndarray, reference: np.ndarray,
                    plan: np.ndarray, target: str = "host") -> list[Path]:
    """The folder of the module docstring for the ``daqp-condensed`` backend's step: CasADi's condensing
    (``capture_condense.c``), the step around DAQP (``mpc_hunt_step.c``, the C the backend's library is built
    from), DAQP's sources (``daqp/``), ``main.c``, a Makefile that needs nothing else, the input and Python's plan."""
    import shutil

    import casadi as ca

    from mpc_hunt.solving.backends.daqp_condensed import (
        DAQP_SOURCES, DAQP_VERSION, NON_FINITE_INPUT, NON_FINITE_PLAN, step_source)

    folder.mkdir(parents=True, exist_ok=True)
    generator = ca.CodeGenerator("capture_condense.c", {"with_header": True})
    generator.add(step.function)
    generator.generate(str(folder) + "/")
    daqp = folder / "daqp"
    for part in ("src", "include"):
        (daqp / part).mkdir(parents=True, exist_ok=True)
        for path in sorted((DAQP_SOURCES / part).glob("*.[ch]")):
            shutil.copyfile(path, daqp / part / path.name)
    shutil.copyfile(DAQP_SOURCES / "LICENSE", daqp / "LICENSE")
    cc = TARGETS[target]["cc"]
    files = {
        "mpc_hunt_step.h": DAQP_H.format(structure=structure, n_theta=len(theta), n_reference=len(reference),
                                         n_plan=len(plan), non_finite_input=NON_FINITE_INPUT,
                                         non_finite_plan=NON_FINITE_PLAN),
        "mpc_hunt_step.c": DAQP_STEP.format(step=step_source(step.function, step.sizes)),
        "main.c": MAIN_C,
        "Makefile": DAQP_MAKEFILE.format(structure=structure, version=DAQP_VERSION,
                                         cc=f"CC = {cc}\n" if cc else ""),
        "input.txt": "\n".join(f"{v:.17g}" for v in np.concatenate([theta, reference])) + "\n",
        "expected.txt": "\n".join(f"{v:.17g}" for v in plan) + "\n",
    }
    if target == "cortex-m7":
        del files["main.c"]
        files.update({"board.c": BOARD_MAIN, "startup.c": BOARD_STARTUP, "board.ld": BOARD_LD,
                      "Makefile": BOARD_MAKEFILE.replace("@STRUCTURE@", str(structure)).replace("@VERSION@",
                                                                                                DAQP_VERSION)})
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return [folder / "capture_condense.c", folder / "capture_condense.h", *(folder / name for name in files), daqp]


def write_step(folder: Path, step, iteration: QPIteration, structure: Structure, theta: np.ndarray,
               reference: np.ndarray, plan: np.ndarray, target: str = "host") -> list[Path]:
    """Write the folder of the module docstring for the backend's ``step`` (a CasADi Function, or the
    ``daqp-condensed`` backend's condensed step) of ``structure``, repeated by ``iteration``'s rule, with the
    inputs ``theta``, ``reference`` and their plan, its Makefile building for ``target`` (:data:`TARGETS`);
    returns the files written. :meth:`mpc_hunt.solving.solver.CaptureSolver.export` calls it with the step it
    has set up."""
    from mpc_hunt.solving.backends.daqp_condensed import CondensedStep

    condensed = isinstance(step, CondensedStep)
    check_export(target, condensed, iteration)
    if condensed:
        return write_condensed(folder, step, structure, theta, reference, plan, target)
    import casadi as ca

    from mpc_hunt.solving.backends.hpipm_codegen import patch
    from mpc_hunt.solving.compiled import casadi_paths

    folder.mkdir(parents=True, exist_ok=True)
    generator = ca.CodeGenerator(f"{NAME}.c", {"with_header": True})
    generator.add(step)
    generator.generate(str(folder) + "/")
    source = folder / f"{NAME}.c"
    source.write_text(patch(source.read_text(encoding="utf-8")), encoding="utf-8")
    iterations = dict(qps=iteration.max_qps, tolerance=float(iteration.tolerance))
    sizes = dict(sz_arg=step.sz_arg(), sz_res=step.sz_res(), sz_iw=step.sz_iw(), sz_w=step.sz_w(), name=step.name())
    files = {
        "mpc_hunt_step.h": WRAPPER_H.format(structure=structure, n_theta=len(theta), n_reference=len(reference),
                                            n_plan=len(plan), **iterations),
        "mpc_hunt_step.c": WRAPPER_C.format(**sizes, **iterations),
        "main.c": MAIN_C,
        "Makefile": MAKEFILE.format(structure=structure, deps=casadi_paths()[1]),
        "input.txt": "\n".join(f"{v:.17g}" for v in np.concatenate([theta, reference])) + "\n",
        "expected.txt": "\n".join(f"{v:.17g}" for v in plan) + "\n",
    }
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return [source, folder / f"{NAME}.h", *(folder / name for name in files)]

