"""Design layer: type synthesis of whole PMs for a motion pattern, verified by the engine,
and dimensional synthesis (:func:`optimize`).

The combinatorial half (motion patterns, the leg pool, compositions, model definitions)
is in :mod:`screwkit.synthesis`, which never calls the solvers; this layer loads each
candidate as a model and checks it with the engine (``docs/synthesis.md``):

* :func:`synthesize_motion` -> :class:`TypeSynthesis` (ranked :class:`SynthesizedPM`);
* :func:`verify_model` -> :class:`Verdict`: full-cycle mobility along a finite motion
  from home (:func:`verification_path`), the pattern's finite invariant, ``J`` at home
  (without the actuation rows of passive legs, :func:`actuation_condition`);
* :func:`verify_candidate` (:class:`VerifyTask` -> :class:`TaskResult`): one candidate's
  verification as a picklable task, for a serial or Dask mapper;
* :func:`optimize` -> :class:`OptimizationResult`: the dimensions of a PM that are best over
  a task (the cells, workloads and trust level of ``screwkit size``) for one objective
  (differential evolution and a local polish) or several (NSGA-II, the Pareto front);
  :func:`evaluate` one candidate (:data:`OBJECTIVES`).
"""

from ._verify import (CHECK_POSES, FINITE_RTOL, PATH_SAMPLES, PoseCheck, Verdict,
                      actuation_condition, verification_path, verify_model)
from ._tasks import TaskResult, VerifyTask, serial_map, verify_candidate
from ._search import (MAX_LEGS, MAX_MIX, MAX_PAIR, MAX_VERIFIED, VARIANTS, SynthesizedPM,
                      TypeSynthesis, synthesize_motion)
from ._evaluate import OBJECTIVES, Objective, Task, evaluate
from ._problem import Problem, parse_constraint, problem
from ._result import OptimizationResult, pareto
from ._optimize import Evaluator, optimize

__all__ = ["CHECK_POSES", "FINITE_RTOL", "MAX_LEGS", "MAX_MIX", "MAX_PAIR", "MAX_VERIFIED",
           "PATH_SAMPLES", "PoseCheck",
           "SynthesizedPM", "TaskResult", "VARIANTS", "TypeSynthesis", "Verdict", "VerifyTask",
           "actuation_condition", "serial_map", "synthesize_motion", "verification_path",
           "verify_candidate", "verify_model",
           "OBJECTIVES", "Objective", "Task", "evaluate", "Problem", "problem",
           "parse_constraint", "OptimizationResult", "pareto", "Evaluator", "optimize"]
