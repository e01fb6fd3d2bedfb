"""Motion of the legs: the gait and its timing, the stance path and foot forces, swing families."""
