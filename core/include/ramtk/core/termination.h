#pragma once
// How a computation ended, shared by every Summary (after Ceres' TerminationType): the kind, for
// code to branch on, beside the summary's `message` in words ("kept 8 (held-out)", "no sphere
// found"). The JSON files keep their documented "termination" values (docs/formats.md): each
// writer maps the kind or writes the message, so no file format changed with the enum.

namespace ramtk {

enum class Termination {
  kNotRun,         // nothing computed yet
  kSuccess,        // finished with a usable result
  kPartial,        // a usable result with a caveat the message names (parameters dropped, poses not converged)
  kNoResult,       // finished without a result to report (no sphere found, target unreachable)
  kNoConvergence,  // stopped at an iteration limit while still improving
  kCancelled,      // the progress callback asked to stop
  kFailure,        // could not run (the message says why)
};

// "not run", "success", "partial", "no result", "no convergence", "cancelled", "failure".
const char* TerminationName(Termination termination);

}  // namespace ramtk
