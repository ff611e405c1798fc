// A fringe cause added at run time beside the table's (ramtk/diagnose/engine/fringe_causes.def): a
// linear extension of the ideal fringe model, given as its basis ∂I_f/∂c per pixel. Once
// registered, `DiagnoseFringeFrames` fits it like the table's linear causes (training tiles,
// held-out score) and names it when it wins, and `SimulateHiddenFringe` plants it when the draw
// names it.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/diagnose/engine/catalogue.h"

namespace ramtk::diagnose {

// The frames of a fringe set as a cause sees them.
struct FringeSequenceView {
  int frames = 0;                       // all frames (phase steps and Gray-code images)
  std::vector<int> phase_frame;         // frame index of phase step k
  std::vector<double> step_shift_rad;   // δ_k of phase step k
  std::vector<int> gray_frame;          // frame index of Gray-code image j
};

// One analysed pixel's ideal-model fit.
struct FringePixelView {
  int x = 0, y = 0;         // camera pixel
  double a = 0, b = 0;      // background A and modulation B (DN)
  double phi = 0;           // wrapped phase (rad): phase frame k is A + B·cos(φ + δ_k)
  double u = 0;             // projector coordinate across the fringes (projector px)
};

struct FringeLinearCause {
  EffectInfo info{"", DataKind::kFringe, "", "", ""};  // its catalogue row (kind kFringe)
  std::vector<std::string> keys;                        // report key of each coefficient
  // Fills `basis` (frames × keys.size()): the change of each frame's intensity per unit coefficient.
  std::function<void(const FringeSequenceView&, const FringePixelView&, Eigen::Ref<Eigen::MatrixXd> basis)> basis;
  // Plants the cause with `magnitude` into rendered frames (CV_32FC1, DN); empty: never planted.
  std::function<void(const FringeSequenceView&, double magnitude, std::vector<cv::Mat>* frames)> plant;
  std::string Validate() const;  // "" when usable, else the first problem as `field: what is wrong`
};

// Adds the cause to the catalogue and to the fringe diagnosis, after the table's causes. InputError
// when it is invalid or its name is already catalogued.
void RegisterFringeCause(const FringeLinearCause& cause);

// The causes registered so far, in registration order.
const std::vector<FringeLinearCause>& RegisteredFringeCauses();

}  // namespace ramtk::diagnose
