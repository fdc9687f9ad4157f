#include <math.h>
#include "capture_step.h"
#include "mpc_hunt_step.h"

int mpc_hunt_hpipm_status(void);

int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective) {
  static const casadi_real *arg[@sz_arg@];
  static casadi_real *res[@sz_res@];
  static casadi_int iw[@sz_iw@ + 1];
  static casadi_real w[@sz_w@ + 1];
  static double start[MPC_HUNT_PLAN];           /* where the QP is linearised: the reference, then each plan */
  int i, k, status;
  double move;
  for (i = 0; i < MPC_HUNT_PLAN; ++i) start[i] = reference[i];
  arg[0] = theta; arg[1] = start; arg[2] = 0; arg[3] = 0;     /* no starting duals */
  res[0] = plan; res[1] = objective; res[2] = 0; res[3] = 0; res[4] = 0;
  for (k = 0; k < @qps@; ++k) {
    if (@name@(arg, res, iw, w, 0)) return -1;
    status = mpc_hunt_hpipm_status();
    for (i = 0; i < MPC_HUNT_PLAN && status == 0; ++i) if (!isfinite(plan[i])) status = 3;
    if (status != 0) {
      for (i = 0; i < MPC_HUNT_PLAN; ++i) plan[i] = start[i];
      return status;
    }
    if (@qps@ == 1) return 0;
    move = 0;
    for (i = 0; i < MPC_HUNT_PLAN; ++i) if (fabs(plan[i] - start[i]) > move) move = fabs(plan[i] - start[i]);
    if (move <= @tolerance@) return 0;
    for (i = 0; i < MPC_HUNT_PLAN; ++i) start[i] = plan[i];
  }
  return 4;
}
