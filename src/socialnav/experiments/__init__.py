"""Layer 4: suites of episodes, their storage and the planners they compare."""
