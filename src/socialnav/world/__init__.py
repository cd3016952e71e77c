"""Layer 1: the world model — occupancy grids, costmaps, ROS map files, rasterization."""
