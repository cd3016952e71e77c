"""Layer 2: trajectory generation, critics, objectives, selection and the local planner."""
