/* The capture step of mpc-hunt, structure @structure@, condensed and solved by DAQP: one call per control step. */
#ifndef MPC_HUNT_STEP_H
#define MPC_HUNT_STEP_H
#define MPC_HUNT_THETA @n_theta@        /* θ: the parameter vector, then the field's smoothing */
#define MPC_HUNT_REFERENCE @n_reference@    /* the reference plan, steps 1..N, defenders in order, (x, y) */
#define MPC_HUNT_PLAN @n_plan@         /* the plan, laid out as the reference */
/* Returns 0 solved; DAQP's exit flag of a failed QP (-1 infeasible, -2 cycling, -3 unbounded, -4 iteration
   limit, ...); @non_finite_input@ a non-finite input or QP, @non_finite_plan@ a non-finite plan, -99 no memory.
   A failed step leaves the reference in ``plan``. Each step starts from the last one's working set (a failed
   warm start is retried cold). ``objective`` may be NULL. Not reentrant: one control loop per process (for
   more, mpc_hunt_daqp_new and mpc_hunt_daqp_solve in mpc_hunt_step.c). */
int mpc_hunt_step(const double *theta, const double *reference, double *plan, double *objective);
#endif
