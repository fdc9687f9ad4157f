static int mpc_hunt_status = -1, mpc_hunt_iterations = 0;
int mpc_hunt_hpipm_status(void) { return mpc_hunt_status; }
int mpc_hunt_hpipm_iterations(void) { return mpc_hunt_iterations; }
