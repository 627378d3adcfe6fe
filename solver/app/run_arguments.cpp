#include "solver/app/run_arguments.hpp"

namespace talus {

const char* to_string(SolverKind solver) {
  return solver == SolverKind::reference ? "reference" : "production";
}

}  // namespace talus
