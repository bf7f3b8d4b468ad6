"""The scripts in examples/ run (each in a fresh temporary folder) and print what they promise.

Each script checks identities of its own (platform and leg equilibrium, a hand-derived
vertical balance); here the printed numbers are compared with the catalog's documented
values (docs/tutorial.md, which tests/test_docs_run.py checks) and the figures are opened.
"""

from __future__ import annotations

import runpy
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))

#: Fragments each example must print (the new ones only need to run).
EXPECT = {
    "paper_3rrprr.py": ["3RRPRR: 3 DOF (1T2R)", "F_a1 =   19.3572", "F_a2 =  -13.4867",
                        "F_a3 =   52.8076", "T_r1=-454.183", "r_i (cm): 85.8201  99.1141  79.7870"],
    "paper_2sps_2spr.py": ["2SPS+2SPR: 4 DOF (1T3R)", "F_a1=116.648  F_a2=-104.481  F_a3=107.028",
                           "F_c3 = (15.5661, 12.9556, 0.5425) kN"],
    "user_pm_yaml.py": ["my_3prs.yaml: valid", "3PRS: independent alpha, beta, Zo", "3 DOF (1T2R)",
                        "F_a1 + F_a2 + F_a3 = 500.000000 N"],
    "trajectory_plot.py": ["{'ok': 201, 'near-singular': 0, 'singular': 0, 'unreachable': 0}", "F_a3            51.817",
                           "wrote 3rrprr_path.csv and 3rrprr_fig5.png"],
    # the locus at alpha + gamma = 2 x 8.617907 deg (the root of det of the paper's J)
    "singularity_map.py": ["441 poses, 441 reachable", "alpha + gamma = 17.2358 deg",
                           "wrote singularity_map.png"],
    "dynamics_3rrprr.py": ["{'ok': 201, 'near-singular': 0, 'singular': 0, 'unreachable': 0", "energy balance"],
}
#: Optional packages an example needs.
NEEDS = {"trajectory_plot.py": ["matplotlib"], "singularity_map.py": ["xarray", "matplotlib"]}


def test_every_example_is_listed():
    assert EXAMPLES, "no examples/"
    assert {"paper_3rrprr.py", "paper_2sps_2spr.py", "user_pm_yaml.py",
            "trajectory_plot.py"} <= {p.name for p in EXAMPLES}
    readme = (ROOT / "examples" / "README.md").read_text(encoding="utf-8")
    for p in EXAMPLES:
        assert p.name in readme, f"examples/README.md does not list {p.name}"


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(script, tmp_path, monkeypatch, capsys):
    for mod in NEEDS.get(script.name, ()):
        pytest.importorskip(mod)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    t0 = time.perf_counter()
    runpy.run_path(str(script), run_name="__main__")
    seconds = time.perf_counter() - t0
    out = capsys.readouterr().out
    assert out.strip(), f"{script.name} printed nothing"
    for piece in EXPECT.get(script.name, ()):
        assert piece in out, f"{script.name} does not print {piece!r}:\n{out}"
    for png in tmp_path.glob("*.png"):                  # figures: a real picture, not blank
        from matplotlib.image import imread

        img = imread(png)
        assert img.shape[0] > 300 and img.shape[1] > 300
        assert img[..., :3].std() > 0.05, f"{png.name} looks blank"
    assert seconds < 60, f"{script.name} took {seconds:.0f} s"
