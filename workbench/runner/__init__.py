"""The run machinery: the `workbench` command, the experiment registry, results and
checkpoints, Dask rows and sweeps, the report and the figures.  The library below it (profiles,
wrenches, limit surfaces, grasps, FEM) never imports it; `make lint` checks the direction."""
