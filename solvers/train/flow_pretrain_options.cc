#include "solvers/train/flow_pretrain_options.h"

#include "core/base/input_error.h"

namespace es {

std::string PretrainSolverName(PretrainSolver solver) {
  switch (solver) {
    case PretrainSolver::kAdam: return "adam";
    case PretrainSolver::kLbfgs: return "lbfgs";
    case PretrainSolver::kLm: return "lm";
  }
  return "unknown";
}

PretrainSolver ParsePretrainSolver(const std::string& name) {
  for (PretrainSolver s :
       {PretrainSolver::kAdam, PretrainSolver::kLbfgs, PretrainSolver::kLm}) {
    if (PretrainSolverName(s) == name) return s;
  }
  throw InputError("unknown pretraining solver '" + name +
                   "'; available: adam, lbfgs, lm");
}

}  // namespace es
