"""Maps layer: a PM over a grid of poses, its singular loci, actuator sizing.

* :func:`map_pm` (``screwkit.map``) -> an :class:`xarray.Dataset`: every cell of a grid of
  1 to 3 independent pose parameters (or random samples in a box) analysed by the batched
  engine, in blocks, serially or on a Dask cluster (bit for bit the same);
* the singular loci: sign changes of ``det J`` refined by batched bisection
  (:func:`locus_list`);
* sizing (:func:`size`): the largest value of every actuator and constraint row over a map
  and a list of workloads (:func:`read_workloads`), with the pose where it occurs;
* files: :func:`write` (NetCDF, Zarr, CSV long format);
* pictures: :func:`plot_map` (heatmaps through :mod:`screwkit.viz`);
* workspace measures (:func:`workspace`): the reachable, singularity-free (connected to
  home) and good-transmission (``LTI >= 0.7``) volumes and their fractions of the box;
* Dask: :func:`client_for` (a local cluster or a running scheduler), :func:`run_tasks`
  (any picklable function over a list, on the cluster; used by ``validate --workers``).

xarray (``screwkit[maps]``) and dask (``screwkit[dask]``) are optional and imported on
first use.
"""

from ._grid import MAX_CELLS, MAX_GRID_DIMS, Grid, make_grid, parse_range
from ._compute import BLOCK, CONDITIONING_CODES, KIND_CODES, LEVEL_CODES
from ._locus import LOCUS_KINDS, REFINE, locus_list
from ._dataset import FORMATS, to_csv, write
from ._map import map_pm
from ._plot import plot_map, quantity_names
from ._sizing import MAX_WORKLOADS, Sizing, extremes, mark_determined, read_workloads, size
from ._dask import client_for, run_tasks
from ._units import map_in_units, sizing_in_units
from ._workspace import GOOD_TRANSMISSION, Workspace, workspace

__all__ = [
    "map_pm", "Grid", "make_grid", "parse_range", "MAX_CELLS", "MAX_GRID_DIMS", "BLOCK",
    "LEVEL_CODES", "CONDITIONING_CODES", "KIND_CODES", "LOCUS_KINDS", "REFINE", "locus_list", "write", "to_csv",
    "FORMATS", "plot_map", "quantity_names", "Sizing", "size", "extremes", "mark_determined", "read_workloads", "MAX_WORKLOADS",
    "client_for", "run_tasks", "map_in_units", "sizing_in_units", "Workspace", "workspace",
    "GOOD_TRANSMISSION",
]
