/* A capture step condensed to a dense QP in its controls and solved by DAQP, warm-started from the last
   solve's working set (mpc-hunt's daqp-condensed backend). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "api.h"
#include "utils.h"
#include "constants.h"

#define MPC_HUNT_NV @nv@        /* the condensed QP's variables: the controls */
#define MPC_HUNT_M @m@          /* its constraints, the @ms@ simple bounds first */
#define MPC_HUNT_MS @ms@
#define MPC_HUNT_NT @n_theta@
#define MPC_HUNT_NR @n_reference@

typedef struct {
  DAQPWorkspace work;
  DAQPProblem qp;
  int ready, flag, iterations;
  int sense[MPC_HUNT_M];
  double H[MPC_HUNT_NV * MPC_HUNT_NV], f[MPC_HUNT_NV], A[(MPC_HUNT_M - MPC_HUNT_MS) * MPC_HUNT_NV + 1];
  double bu[MPC_HUNT_M], bl[MPC_HUNT_M], plan0[MPC_HUNT_NR], P[MPC_HUNT_NR * MPC_HUNT_NV], c0;
  double x[MPC_HUNT_NV], lam[MPC_HUNT_M];
  const casadi_real *arg[@sz_arg@ + 1];
  casadi_real *res[@sz_res@ + 1];
  casadi_int iw[@sz_iw@ + 1];
  casadi_real w[@sz_w@ + 1];
} mpc_hunt_daqp;

mpc_hunt_daqp *mpc_hunt_daqp_new(void) { return (mpc_hunt_daqp *) calloc(1, sizeof(mpc_hunt_daqp)); }

void mpc_hunt_daqp_free(mpc_hunt_daqp *s) {
  if (!s) return;
  if (s->ready) { free_daqp_workspace(&s->work); free_daqp_ldp(&s->work); }
  free(s);
}

int mpc_hunt_daqp_iterations(const mpc_hunt_daqp *s) { return s->iterations; }
int mpc_hunt_daqp_flag(const mpc_hunt_daqp *s) { return s->flag; }

static int mpc_hunt_finite(const double *x, int n) {
  int i;
  for (i = 0; i < n; ++i) if (!isfinite(x[i])) return 0;
  return 1;
}

/* One step: 0 solved; DAQP's exit flag of a failed QP (< 0); @non_finite_input@ a non-finite input or QP,
   @non_finite_plan@ a non-finite plan. A failed step leaves the reference in ``plan``. ``objective`` may be NULL. */
int mpc_hunt_daqp_solve(mpc_hunt_daqp *s, const double *theta, const double *reference, double *plan,
                        double *objective) {
  DAQPResult r;
  int i, j, attempt, mask = DAQP_UPDATE_Rinv | DAQP_UPDATE_M | DAQP_UPDATE_v | DAQP_UPDATE_d | DAQP_UPDATE_sense;
  double value;
  s->iterations = 0;
  s->flag = @non_finite_input@;
  for (i = 0; i < MPC_HUNT_NR; ++i) plan[i] = reference[i];
  if (!mpc_hunt_finite(theta, MPC_HUNT_NT) || !mpc_hunt_finite(reference, MPC_HUNT_NR)) return s->flag;
  s->arg[0] = theta; s->arg[1] = reference;
  s->res[0] = s->H; s->res[1] = s->f; s->res[2] = s->A; s->res[3] = s->bu; s->res[4] = s->bl;
  s->res[5] = s->plan0; s->res[6] = s->P; s->res[7] = &s->c0;
  if (@condense@(s->arg, s->res, s->iw, s->w, 0)) return s->flag;
  if (!mpc_hunt_finite(s->H, MPC_HUNT_NV * MPC_HUNT_NV) || !mpc_hunt_finite(s->f, MPC_HUNT_NV)
      || !mpc_hunt_finite(s->A, (MPC_HUNT_M - MPC_HUNT_MS) * MPC_HUNT_NV) || !mpc_hunt_finite(s->bu, MPC_HUNT_M)
      || !mpc_hunt_finite(s->bl, MPC_HUNT_M)) return s->flag;
  for (attempt = 0; attempt < 2; ++attempt) {      /* from the last working set, then (if that fails) cold */
    if (!s->ready) {
      memset(s->sense, 0, sizeof s->sense);
      s->qp.n = MPC_HUNT_NV; s->qp.m = MPC_HUNT_M; s->qp.ms = MPC_HUNT_MS;
      s->qp.H = s->H; s->qp.f = s->f; s->qp.A = s->A; s->qp.bupper = s->bu; s->qp.blower = s->bl;
      s->qp.sense = s->sense; s->qp.break_points = 0; s->qp.nh = 0; s->qp.problem_type = 0;
      s->work.settings = 0;
      s->flag = setup_daqp(&s->qp, &s->work, 0);
      if (s->flag < 0) return s->flag;
      s->ready = 1;
      attempt = 1;                                     /* already cold */
    } else if (attempt == 0) {
      s->qp.sense = s->work.sense;                     /* the last solve's working set */
      if ((s->flag = daqp_update_ldp(mask, &s->work, &s->qp)) < 0) continue;
    } else {
      memset(s->sense, 0, sizeof s->sense);
      s->qp.sense = s->sense;
      if ((s->flag = daqp_update_ldp(mask, &s->work, &s->qp)) < 0) return s->flag;
    }
    r.x = s->x; r.lam = s->lam;
    daqp_solve(&r, &s->work);
    s->iterations += r.iter;
    s->flag = r.exitflag;
    if (s->flag > 0) break;
  }
  if (s->flag <= 0) return s->flag;
  for (i = 0; i < MPC_HUNT_NR; ++i) {
    value = s->plan0[i];
    for (j = 0; j < MPC_HUNT_NV; ++j) value += s->P[j * MPC_HUNT_NR + i] * s->x[j];
    plan[i] = value;
  }
  if (!mpc_hunt_finite(plan, MPC_HUNT_NR)) {
    for (i = 0; i < MPC_HUNT_NR; ++i) plan[i] = reference[i];
    return s->flag = @non_finite_plan@;
  }
  if (objective) {
    value = s->c0;
    for (i = 0; i < MPC_HUNT_NV; ++i) {
      value += s->f[i] * s->x[i];
      for (j = 0; j < MPC_HUNT_NV; ++j) value += 0.5 * s->x[i] * s->H[j * MPC_HUNT_NV + i] * s->x[j];
    }
    *objective = value;
  }
  return 0;
}
