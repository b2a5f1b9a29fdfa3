"""Dimensional synthesis: problems (``load_problem``), vectorised objectives (``Evaluator``),
optimisers (``synthesize``) and executors (in-process, local processes, Dask)."""
from .evaluate import Evaluation, Evaluator
from .executors import DaskCluster, InProcess, LocalProcesses, make_executor
from .optimize import SynthesisResult, synthesize
from .problem import Problem, load_problem, problem_from_dict

__all__ = ["DaskCluster", "Evaluation", "Evaluator", "InProcess", "LocalProcesses", "Problem", "SynthesisResult",
           "load_problem", "make_executor", "problem_from_dict", "synthesize"]
