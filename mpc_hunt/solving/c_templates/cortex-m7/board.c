/* The capture step on a bare-metal Cortex-M7 (qemu-system-arm -M mps2-an500 -icount shift=0 -semihosting):
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
