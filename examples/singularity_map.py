"""A map of the 2SPS+2SPR: where is its actuation singularity, and how large do the forces get?

The paper's 2SPS+2SPR has an actuation singularity close to its home pose. This script maps
the (alpha, gamma) plane at beta = 0, Zo = 80 cm (21 x 21 poses, degrees) under the paper's
workload: the normalised condition number, the active forces, and the singular locus where
det J changes sign between neighbouring cells, refined by bisection. Independently of the map,
docs/tutorial.md finds det J = 0 at alpha = gamma = 8.617907119683968 deg on this plane (the
root of det of the paper's own J, tests/test_trajectory.py): on the locus alpha + gamma should
be 2 x 8.6179 = 17.2358 deg. Writes singularity_map.png (needs xarray and matplotlib:
pip install "screwkit[maps,plot]").

Run: python examples/singularity_map.py
"""

import numpy as np

import screwkit
from screwkit.maps import plot_map

ds = screwkit.map("2SPS+2SPR", {"alpha": (-2, 12, 21), "gamma": (-2, 12, 21)},
                  fix={"beta": 0, "Zo": 80}, degrees=True)
kinds = ds["locus_kind"].attrs["flag_meanings"].split()
print(f"{ds.attrs['pm']}: {ds.attrs['cells']} poses, {int(ds['reachable'].sum())} reachable, "
      f"{int(ds['ok'].sum())} ok")
cn = ds["condition_number"].values
print(f"normalised condition number: {np.nanmin(cn):.1f} .. {np.nanmax(cn):.3g}")
sums = ds["locus_alpha"].values + ds["locus_gamma"].values
print(f"singular locus: {sums.size} crossings of det J = 0 "
      f"({', '.join(sorted({kinds[k] for k in ds['locus_kind'].values}))}); "
      f"alpha + gamma = {sums.mean():.4f} deg (spread {np.ptp(sums):.1e})")
print(f"expected from the root of det J on alpha = gamma: {2 * 8.617907119683968:.4f} deg")
unit = ds["F_a1"].attrs["units"]
far = (ds["alpha"] + ds["gamma"]) < 12.0                    # 5 deg or more from the locus
for k in ("F_a1", "F_a2", "F_a3", "F_a4"):
    v = ds[k].where(far).values
    print(f"  {k}: largest |value| {np.nanmax(np.abs(v)):7.1f} {unit} where alpha + gamma < 12 deg, "
          f"{np.nanmax(np.abs(ds[k].values)):8.1f} {unit} on the whole map")
plot_map(ds, "singularity_map.png", ("conditioning", "forces"))
print("wrote singularity_map.png")
assert abs(sums.mean() - 2 * 8.617907119683968) < 1e-3
