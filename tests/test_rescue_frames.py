"""A pose the first Newton run leaves unconverged: its rows are formed at the unknowns the
solve returns, whatever the continuation and the polish did to the workspace's frames.

The two poses of the 3SPU+RPRR below (out of its reach: the solve flags them unsolved)
send the kernel through the continuation and the polish, whose Newton runs overwrite both
frame buffers without improving the residual.  The rows, conditioning and statics of the
solve must be those of the frames formed afresh at the returned unknowns (a second launch
that solves nothing), the same arrays bit for bit.
"""

import numpy as np

import screwkit
from screwkit.engine._chains import chains_of
from screwkit.engine._launch import run_poses
from screwkit.engine._solve import predictor_of

# Xo Yo Zo alpha beta gamma (cm, rad): given Xo, Zo, alpha, beta out of the PM's reach
POSES = np.array([
    [1.0605185390540662e+01, 0.0, 7.5458965035215812e+01, -3.3023857391167255e-02,
     -1.8637242130909554e-01, 0.0],
    [9.5050671221654817e+00, 0.0, 7.5864376577158126e+01, -3.9379356358295384e-02,
     -1.8568048498983597e-01, 0.0],
    [2.0, 0.0, 80.0, 0.05, -0.05, 0.0],          # a reachable pose beside them
])
F, T = np.array([10.0, -20.0, 30.0]), np.array([100.0, 0.0, -50.0])


def test_rows_are_those_of_the_returned_unknowns():
    ch = chains_of(screwkit.load_pm("3SPU+RPRR"))
    P6 = ch.full_params({k: POSES[:, i] for k, i in
                         (("Xo", 0), ("Zo", 2), ("alpha", 3), ("beta", 4))}, len(POSES))
    solved = run_poses(ch.flat, predictor_of(ch), P6, F=F, T=T, workers=1)
    # the first two went through the rescue and stayed unsolved; the third is solved
    assert list(np.asarray(solved["how"])) == [2, 2, 0]
    again = run_poses(ch.flat, predictor_of(ch), P6, X=np.asarray(solved["X"]), F=F, T=T,
                      workers=1)
    for key in ("J", "singular_values", "condition_number", "values"):
        np.testing.assert_array_equal(np.asarray(solved[key]), np.asarray(again[key]),
                                      err_msg=key)
