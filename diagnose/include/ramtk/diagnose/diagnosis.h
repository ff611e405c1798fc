// The result of a diagnosis: what the current model gets wrong, the named cause, the extension's
// parameters and its held-out gain. Every data kind (fringe images, robot/ball measurements, laser
// device logs) fills the same structure, so one JSON writer and one report serve them all.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace ramtk::diagnose {

// The kinds of measured data `ramtk diagnose` handles.
enum class DataKind { kFringe, kRobot, kLaser };
const char* DataKindName(DataKind kind);  // "fringe", "robot", "laser"

// Cause names that are not catalogue effects.
inline constexpr const char* kNoEffect = "none";            // residual is white at the expected level
inline constexpr const char* kUnexplained = "unexplained";  // structure no catalogued effect explains

// One candidate model (the current model itself is the candidate named kNoEffect with 0 parameters).
struct CandidateFit {
  std::string effect;                        // catalogue name (see catalogue.h) or kNoEffect
  int num_parameters = 0;                    // extra parameters over the current model
  std::map<std::string, double> parameters;  // estimates; the unit is part of the key, e.g. "latency_s"
  std::map<std::string, double> sigmas;      // their standard deviations (same keys), when known
  double train_rms = 0.0;                    // residual RMS on the fitting folds
  double heldout_rms = 0.0;                  // residual RMS on the held-out folds (cross-validated)
  int heldout_count = 0;                     // residuals behind heldout_rms
  double score = 0.0;                        // selection score, lower is better (model_selection.h)
  double weight = 0.0;                       // relative evidence in [0, 1] over all candidates
};

// A picture written next to the report.
struct Picture {
  std::string file;     // path relative to the report's folder
  std::string caption;  // what it shows, one sentence
};

struct Diagnosis {
  DataKind kind = DataKind::kRobot;
  std::string data;   // what was diagnosed (path or description)
  std::string unit;   // unit of the residuals ("mm", "px", "rad", "DN", "s")
  std::string model;  // the current model, e.g. "nominal", "calibrated"

  // Step 1–2: the residual of the current model against the expected noise.
  int num_residuals = 0;
  double noise_floor_rms = 0.0;       // expected RMS from the noise model alone
  double residual_rms = 0.0;          // current model, all data
  bool structure_found = false;       // false: white at the expected level (a valid answer)
  double structure_p_value = 1.0;     // smallest (corrected) p-value of the structure tests
  std::vector<std::string> findings;  // one line per test / observation, for people

  // Step 3: the named cause.
  std::string cause = kNoEffect;             // catalogue name, kNoEffect or kUnexplained
  std::map<std::string, double> parameters;  // of the chosen extension
  std::map<std::string, double> sigmas;
  double confidence = 0.0;               // in [0, 1]: evidence weight of the chosen candidate
  std::string explaining_variable;       // for kUnexplained: the measured variable that explains it
  std::vector<CandidateFit> candidates;  // all fitted, best first

  // Step 4: held-out gain of the chosen extension.
  double rms_before = 0.0;      // held-out RMS, current model
  double rms_after = 0.0;       // held-out RMS, extended model
  double excess_removed = 0.0;  // share of the excess over the noise floor removed (see ExcessRemoved)

  std::vector<Picture> pictures;
};

// Share of the excess mean square over the noise floor that an extension removes:
// (before² − after²) / (before² − floor²), clamped to [−1, 1]; 0 when there is no excess.
double ExcessRemoved(double rms_before, double rms_after, double noise_floor_rms);

}  // namespace ramtk::diagnose
