static int mpc_hunt_status = -1, mpc_hunt_iterations = 0, mpc_hunt_iter_cap = 0;
int mpc_hunt_hpipm_status(void) { return mpc_hunt_status; }
int mpc_hunt_hpipm_iterations(void) { return mpc_hunt_iterations; }
/* The next calls' iteration cap, below the one the step was generated with (0: that one). */
void mpc_hunt_hpipm_set_iter_max(int cap) { mpc_hunt_iter_cap = cap; }
