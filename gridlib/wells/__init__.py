"""Wells along any path: trajectories, the cells they cross, their connection factors."""
