"""The layout of a flattened model: which array of the kernels' model tuple holds what
(private; plain Python, shared by the flattening in :mod:`screwkit.engine._flat` and by the
kernels, which read these names as compile-time constants).

The model tuple ``M`` (every kernel takes it first):

====  ========  =============  ======================================================
idx   name      dtype, shape   holds
====  ========  =============  ======================================================
0     D         f8 (n, m, 3)   home joint axes (world)
1     P         f8 (n, m, 3)   a point of each home axis
2     ROT       f8 (n, m)      rotation per unit joint value (1 for R and H, 0 else)
3     TRA       f8 (n, m)      translation per unit value (1 for P and Pa, pitch for H)
4     QS        f8 (n, m)      the Newton unknown is ``q / QS`` (``L`` for P and Pa)
5     TRN       f8 (n, m)      translation per unit unknown over ``L`` (the normalised
                               twist's)
6     BAR       f8 (n, m, 3)   home bar vector of a parallelogram Pa (0 elsewhere)
7     HINGE     f8 (n, m, 3)   its hinge ``b x D / |b|``
8     BLEN      f8 (n, m)      ``|b|`` (0 where no Pa)
9     KIND      i8 (n, m)      joint kind: 0 R, 1 P, 2 H, 3 Pa
10    LEG       i8 (n, 5)      joints, actuated slot, active (1) or passive (0), row of
                               its actuation row in J (-1 for a passive leg), slot of
                               its first S joint's first part (-1: no S joint)
11    PLAT      f8 (28,)       base frame R0 (9, row-major), p0 (3); platform at home
                               Rh (9), ph (3); the model's centroid c (3) and length L
12    ORDER     i8 (5,)        Euler axes (3), intrinsic (1/0), proper (1/0)
13    A         f8 (n, 3)      base points A_i (world)
14    AP        f8 (n, 3)      platform points a_i (platform frame)
15    PTS       i8 (n, p, 3)   the leg's named points: (type, i, j), type 0 A, 1 a,
                               2 joint i, 3 the meeting point of the axes i and j
16    DIRS      i8 (n, d, 4)   the leg's reference directions (type, a1, a2, negate):
                               see ``DIR_*``; entries refer to earlier ones only
17    GRP       i8 (n, g, 6)   constraint member groups: kind (0 couple, 1 force),
                               named point, dimension, three reference directions
18    TPL       i8 (n, 8)      row template: generic, k, groups, actuation kind (0 none,
                               1 line, 2 least-norm), its two points, first constraint
                               row, references of the generic rule
19    GREF      i8 (n, k, 2)   the generic rule's reference wrenches: (0 force through A
                               / 1 couple, direction)
20    ROWS      i8 (r, 4)      per row of J: leg, kind (0 actuation, 1 force, 2 couple,
                               3 screw), named point (-1 none), torque effort (1/0)
21    REV       f8 (k, 6)      the legs whose linear actuator carries the leg's length
                               (``screwkit.engine._reversal``): leg, row of its
                               unknown in ``X``, sign of its home length, the limit at
                               or beyond which it is reversed (``sign X[row] <=
                               limit``), the home length, the unknown's scale
====  ========  =============  ======================================================

The pose parametrisation travels beside it (a representation singularity solves with other
unknowns): ``unk`` (i8, the indices in ``PARAMS`` of the dependent parameters) and ``xs``
(their scales, ``L`` for lengths).  The unknowns of a pose are ``X = [x (nu); q / QS (n m)]``,
leg-major: slot ``j`` of leg ``i`` is ``X[nu + i m + j]``.
"""

D, P, ROT, TRA, QS, TRN, BAR, HINGE, BLEN, KIND, LEG, PLAT, ORDER, A, AP = range(15)
PTS, DIRS, GRP, TPL, GREF, ROWS, REV = range(15, 22)

# joint kinds
K_R, K_P, K_H, K_PA = 0, 1, 2, 3
# LEG columns
L_SIZE, L_ACT, L_ACTIVE, L_AROW, L_BALL = 0, 1, 2, 3, 4
# PLAT offsets
P_R0, P_P0, P_RH, P_PH, P_C, P_L = 0, 9, 12, 21, 24, 27
# named point types
PT_A, PT_a, PT_JOINT, PT_MEET = 0, 1, 2, 3
# reference direction types
(DIR_LEG, DIR_BASE, DIR_PLATFORM, DIR_BASE_OA, DIR_PLATFORM_OA, DIR_BASE_TANGENT,
 DIR_PLATFORM_TANGENT, DIR_JOINT, DIR_PERPENDICULAR, DIR_ALONG) = range(10)
# TPL columns
T_GENERIC, T_K, T_NG, T_AKIND, T_AP1, T_AP2, T_CROW, T_NGREF = range(8)
# actuation kinds
A_NONE, A_LINE, A_LEAST_NORM = 0, 1, 2
# group kinds, row kinds
G_COUPLE, G_FORCE = 0, 1
R_ACTUATION, R_FORCE, R_COUPLE, R_SCREW = 0, 1, 2, 3

#: Poses a thread solves together (the lanes of a block: :mod:`._block`).  64 rather than 32
#: (2-6 % less CPU a pose of the whole analysis, measured 2026-12-05; on the AMD EPYC of
#: 2026-12-06, 32 took the path from 1.67-1.89M to 1.22-1.55M samples a second and random
#: poses from 1.12M to 0.9M) or 128 (slower than 64 again, by as much; on the EPYC within
#: the noise, and a warm pose's workspaces larger).
BLOCK = 64
#: The parallel kernel's threads and pieces (``_threads.piece_of``): the fewest poses a
#: thread worth a launch on it; a launch's poses cut into about ``PIECES_PER_THREAD``
#: pieces a thread, whole blocks, each of at least ``MIN_PIECE`` poses (smaller towards
#: the end of a launch: ``_threads.piece_span``).
MIN_PER_THREAD = 256
PIECES_PER_THREAD = 8
MIN_PIECE = 256

#: Length-normalised closure residual regarded as converged (success).
CONVERGED = 1e-10
#: Largest residual returned as a (poor) solution rather than unreachable.
ACCEPTED = 1e-6
#: Residual at which the iteration stops.
STOP = 1e-12
#: Relative size below which a null-space test quantity counts as zero.
ZERO = 1e-8
#: Smallest |cosine| (or Gram-Schmidt remainder) of a reference direction chosen at home.
REF_MIN = 0.2
#: Below this |cosine| (remainder) at a pose the basis is flagged as ill-defined there.
REF_FLAG = 1e-3
#: Relative threshold on singular values below which a direction counts as lost.
RANK_RTOL = 1e-8
#: Above this condition number the statics is solved by the pseudo-inverse.
REFINE = 1e3

#: Transmission indices: below this ``|w| L / |V|`` a twist counts as a translation (no
#: axis, no arm).
TRANSLATION_RTOL = 1e-12
#: Transmission indices: a row whose leverage in its rows' range is below
#: ``1 - LEVERAGE_RTOL`` is redundant (the other rows keep the rank without it; their
#: smallest singular value stays above about ``1e-4`` of the largest).
LEVERAGE_RTOL = 1e-8

#: The columns of a leg's entry in the lines of the transmission indices' joints
#: (``_indices.pose_lines``): the point and axis of its platform-side joint, the point and
#: axis of the joint after its actuator, its actuated joint's unit twist.
LN_OUT_Q, LN_OUT_D, LN_IN_Q, LN_IN_D, LN_V = 0, 3, 6, 9, 12
LINE_WIDTH = 18

#: The rows workspace of a block of lanes (``_block.make_rows_lanes``): the legs' contexts,
#: named points, directions and twists; the template legs' rows, their scales, each leg's
#: scratch and status; the scratch of ``_members.template_lanes``; the lanes' centroids,
#: spreads and origins (``_statics.spread_lanes``).
RL_CTX, RL_PV, RL_DV, RL_TW, RL_J, RL_SCALE, RL_SC, RL_R, RL_V, RL_BASIS, RL_SP = range(11)

#: The outputs of the analysis kernel (``_driver``), in its order (``_launch``), and its
#: flags: solve, rows, statics, continuation, actuated twists, the lines of the transmission
#: indices' joints and the platform, the legs' orientation in ``OUT_DET`` (1/0 each).
#: ``OUT_DET``: the sign of a square ``J``'s determinant, times its legs' orientation
#: (``_orient.leg_orientation``) with ``F_ORIENT``.  ``OUT_EXCESS``: a path level's samples'
#: excess (``_levels.moved_beyond``; no rows otherwise).  ``OUT_REVERSED``: each pose's legs
#: whose actuator its unknowns run through zero length (bit ``i`` for leg ``i``, ``REV``).
(OUT_X, OUT_RES, OUT_ITS, OUT_HOW, OUT_SING, OUT_J, OUT_SCALE, OUT_ROWS_OK, OUT_STRUCT,
 OUT_CENTRE, OUT_LENGTH, OUT_SV, OUT_RANK, OUT_COND, OUT_CRANK, OUT_CCOND, OUT_VALUES,
 OUT_EQ, OUT_AMP, OUT_DET, OUT_TWISTS, OUT_LINES, OUT_PLATFORM, OUT_EXCESS,
 OUT_REVERSED) = range(25)
#: ``REV``'s columns.
RV_LEG, RV_ROW, RV_SIGN, RV_LIMIT, RV_HOME, RV_SCALE = range(6)
F_SOLVE, F_ROWS, F_STATICS, F_CONTINUATION, F_TWISTS, F_LINES, F_ORIENT = range(7)

#: A path level's stencils (``_levels.level_stencil``), a sample's start: the columns, its
#: kind (``SK_*``), the four weights, the four rows of the unknowns it reads (the cubic's
#: nodes: the left neighbour's left, the left and right neighbours, the right one's right;
#: exact as floats); the kinds, the left neighbour's unknowns, the right one's, the linear
#: interpolation of the two (``w``, the right one's weight, in ``ST_W``), the cubic.
ST_KIND, ST_W, ST_ROW = 0, 1, 5
STENCIL_WIDTH = 9
SK_LEFT, SK_RIGHT, SK_LINEAR, SK_CUBIC = 0, 1, 2, 3

#: A path's levels solved in one launch (``_path_loop``): the header of its integer state,
#: the samples, the samples to solve before the launch returns (at the end of the level
#: that reaches them), the samples of the level left for Python's retries (0: none),
#: whether the threads may wait for each other between levels (numba's workqueue layer,
#: which runs each of a launch's ranges on a thread of its own), the fill (0: none begun;
#: else one more than the gap of the fill's grid it goes on from, ``_path_loop``), whether
#: the last level was smooth (``_path_loop.take_level``; kept from launch to launch, so
#: that the levels are the same whatever the budgets); then
#: its arrays of ``N`` each (``LV_*``): solved (1: an anchor or a level's sample, 2: a
#: sample of the fill), iterations, how, singular beta, kept (the
#: rows formed in the level's launch stay), and the loop's scratch (the solved samples in
#: order, twice, the gaps of a level, whether each sample converged).  The float state: the
#: given parameters ``(N, 6)`` of every sample, then the residuals ``(N,)``, then the
#: samples' compliances ``(N, rows)`` where each sample has its own.
LH_N, LH_BUDGET, LH_RETRY, LH_TEAM, LH_FILL, LH_SMOOTH = range(6)
LH_SIZE = 6
#: The shared words of a path's levels run by a team of threads (``_driver.team_levels``,
#: with ``LH_TEAM`` set): the levels released by the lead thread, the threads arrived at the
#: end of a level (all levels counted), the pieces taken of the level, its samples, the
#: solved samples, which of the two lists holds them, the samples solved in the launch.
SY_READY, SY_ARRIVED, SY_TAKEN, SY_G, SY_N, SY_WHICH, SY_DONE = range(7)
SY_SIZE = 8
#: The fill of a path (``_path_loop.fill_level``): once a level is smooth (at most half its
#: samples took a Newton step, one in ``FILL_SHARE`` more than one or did not converge)
#: and no gap between the solved samples is wider than ``FILL_GAP``, every sample left is
#: started from the cubic through the solved samples around its gap, in the path's order
#: (levels of at least ``FILL_PORTION`` samples, or the launch's budget).
FILL_GAP = 32
FILL_SHARE = 64
FILL_PORTION = 4096
LV_SOLVED, LV_ITS, LV_HOW, LV_SING, LV_KEPT, LV_IDX, LV_IDX2, LV_GAPS, LV_GOOD = range(9)
LV_ROWS = 9
#: Rows of the template members' scratch ``SC (NSC, ls)`` (``_members``): the null space's
#: flag, the groups' flag (1 or 0), the basis' smallest remainder, the longest row, a
#: largest residual, a reference's projection and remainder, the actuation's scale and flag
#: (1: defined, not dependent), the template's status; then the pair search's two sets of
#: ``PAIR_ROWS`` rows from ``SC_PAIR`` on (``_members._pair_lanes``: the best pair's squared
#: cross product, its rows' squared norms, its cross product).
(SC_NULL, SC_GROUPS, SC_WORST, SC_BIG, SC_RES, SC_P0, SC_P1, SC_P2, SC_REM, SC_SCALE, SC_ACT,
 SC_STATUS, SC_PAIR) = range(13)
PAIR_ROWS = 6
NSC = SC_PAIR + 2 * PAIR_ROWS
