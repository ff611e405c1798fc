// The result of a diagnosis: what the current model gets wrong, the named cause, the extension's
// parameters and its held-out gain. Every data kind (fringe images, robot/ball measurements, laser
// device logs) fills the same structure, so one JSON writer and one report serve them all.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ramtk/report/figure.h"

namespace ramtk::diagnose {

// The kinds of measured data `ramtk diagnose` handles.
enum class DataKind { kFringe, kRobot, kLaser };
const char* DataKindName(DataKind kind);  // "fringe", "robot", "laser"

// Cause names that are not catalogue effects.
inline constexpr const char* kNoEffect = "none";            // residual is white at the expected level
inline constexpr const char* kUnexplained = "unexplained";  // structure no catalogued effect explains
inline constexpr const char* kAmbiguous = "ambiguous";      // look-alike candidates the data cannot separate
inline constexpr const char* kNotObservable = "not_observable";  // the current model absorbs the candidate
inline constexpr const char* kImplausible = "implausible";  // the best fit lies outside its cause's physical bounds

// One candidate model (the current model itself is the candidate named kNoEffect with 0 parameters).
struct CandidateFit {
  std::string effect;                        // catalogue name (see catalogue.h) or kNoEffect
  int num_parameters = 0;                    // extra parameters over the current model
  std::map<std::string, double> parameters;  // estimates; the unit is part of the key, e.g. "latency_s"
  std::map<std::string, double> sigmas;      // their standard deviations (same keys), when known
  double train_rms = 0.0;                    // residual RMS on the fitting folds
  double heldout_rms = 0.0;                  // residual RMS on the held-out folds (cross-validated)
  int heldout_count = 0;                     // residuals behind heldout_rms
  std::vector<double> heldout_group_ssr;     // held-out sum of squares per cross-validation group (fringe:
                                             // image tile), for paired comparisons; empty if not kept
  double score = 0.0;                        // selection score, lower is better (model_selection.h)
  double weight = 0.0;                       // relative evidence in [0, 1] over all candidates
  double absorbed_share = -1.0;              // share of the candidate the current model absorbs (< 0: not computed)
  double signature_cos = -1.0;               // |cos| of the angle between its fitted correction and the chosen
                                             // candidate's (1 = look-alike; < 0: not computed)
  std::string implausible;                   // why a fitted value is outside the candidate's plausibility bounds
                                             // (empty: plausible); an implausible candidate is never named
};

// One cause of a verdict that names several (robot data: forward selection), in the order kept.
struct CauseStep {
  std::string effect;
  int num_parameters = 0;
  double rms_before = 0.0;      // held-out RMS before this cause was added
  double rms_after = 0.0;       // held-out RMS with it
  double excess_removed = 0.0;  // its share of the current model's excess over the noise floor
  std::map<std::string, double> parameters;
  std::map<std::string, double> sigmas;
};

// A picture written next to the report.
struct Picture {
  std::string file;     // path relative to the report's folder (empty: no PNG was drawn)
  std::string caption;  // what it shows, one sentence
  std::optional<report::Figure> figure;  // the plotted data (none for images such as a residual map)
};

struct Diagnosis {
  DataKind kind = DataKind::kRobot;
  std::string data;   // what was diagnosed (path or description)
  std::string unit;   // unit of the residuals ("mm", "px", "rad", "DN", "s")
  std::string model;  // the current model, e.g. "nominal", "calibrated"

  // Step 1–2: the residual of the current model against the expected noise.
  int num_residuals = 0;
  double noise_floor_rms = 0.0;       // expected RMS from the noise model alone
  std::map<std::string, double> noise_model;         // noise-level function estimated from the data, when the
                                                     // kind has one (fringe: a_DN2, b_DN, c of a + b·I + c·I²)
  std::map<std::string, double> noise_model_sigmas;  // their standard deviations
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
  std::vector<std::string> partial;      // for kUnexplained: catalogue candidates that explain part of it
  std::vector<std::string> look_alikes;  // for kAmbiguous / kNotObservable: the candidates concerned
  std::string separate_with;             // for kAmbiguous: what data would separate them
  std::vector<CandidateFit> candidates;  // all fitted, best first
  // Every cause kept, each with its own held-out gain, when the verdict names several (the first is
  // `cause`); rms_after and excess_removed below are then those of all of them together.
  std::vector<CauseStep> causes;

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
