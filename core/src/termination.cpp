#include "ramtk/core/termination.h"

namespace ramtk {

const char* TerminationName(Termination termination) {
  switch (termination) {
    case Termination::kNotRun:
      return "not run";
    case Termination::kSuccess:
      return "success";
    case Termination::kPartial:
      return "partial";
    case Termination::kNoResult:
      return "no result";
    case Termination::kNoConvergence:
      return "no convergence";
    case Termination::kCancelled:
      return "cancelled";
    case Termination::kFailure:
      return "failure";
  }
  return "?";
}

}  // namespace ramtk
