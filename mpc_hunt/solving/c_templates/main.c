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
      fprintf(stderr, "input: state %d: %s[%d] missing (a state is %d numbers)\n", state, what, i,
              MPC_HUNT_THETA + MPC_HUNT_REFERENCE);
      return -1;
    }
    if (got < 0) {
      fprintf(stderr, "input: state %d: %s[%d]: a token longer than %d characters\n", state, what, i, TOKEN - 1);
      return -1;
    }
    x[i] = strtod(token, &end);
    if (end == token || *end) {
      fprintf(stderr, "input: state %d: %s[%d]: '%s' is not a number\n", state, what, i, token);
      return -1;
    }
    if (!isfinite(x[i])) {
      fprintf(stderr, "input: state %d: %s[%d]: '%s' is not finite\n", state, what, i, token);
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
    if (timed) fprintf(stderr, "time_us %.3f\n", (end.tv_sec - start.tv_sec) * 1e6 + (end.tv_nsec - start.tv_nsec) * 1e-3);
    for (i = 0; i < MPC_HUNT_PLAN; ++i) printf("%.17g\n", plan[i]);
    if (status != 0) { fprintf(stderr, "state %d: step status %d\n", state, status); failed = 1; }
    ++state;
  }
  if (read < 0) return 2;
  if (state == 0) { fprintf(stderr, "input: no state\n"); return 2; }
  return failed;
}
