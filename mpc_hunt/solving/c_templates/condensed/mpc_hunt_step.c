#include "capture_condense.h"
#include "mpc_hunt_step.h"
@step@
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective) {
  static mpc_hunt_daqp *s = 0;
  int i;
  if (!s && !(s = mpc_hunt_daqp_new())) {
    for (i = 0; i < MPC_HUNT_PLAN; ++i) plan[i] = reference[i];
    return -99;
  }
  return mpc_hunt_daqp_solve(s, theta, reference, plan, objective);
}
