/* The capture step of mpc-hunt, structure @structure@: one call per control step. */
#ifndef MPC_HUNT_STEP_H
#define MPC_HUNT_STEP_H
#define MPC_HUNT_THETA @n_theta@        /* θ: the parameter vector, then the field's smoothing */
#define MPC_HUNT_REFERENCE @n_reference@    /* the reference plan, steps 1..N, defenders in order, (x, y) */
#define MPC_HUNT_PLAN @n_plan@         /* the plan, laid out as the reference */
/* At most @qps@ QP(s) a step, each linearised at the last one's plan, until no position moves by
   more than @tolerance@ m. Returns 0 solved; HPIPM's status of a failed QP: 1 iteration limit, 2 minimum step,
   3 NaN; 4 no convergence in @qps@ QPs; -1 the call failed. After a failed QP ``plan`` holds the last usable plan
   of the step (the reference, if none). ``objective`` may be NULL. Not reentrant: one control loop per process. */
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective);
#endif
