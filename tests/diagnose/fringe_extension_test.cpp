// Adding a fringe cause outside the table (docs/architecture.md, "Where to add things"): a
// test-only linear cause registered from this file, planted into a hidden draw's frames, named by
// the diagnosis with its coefficient recovered. Its own executable: the registration is
// process-wide.
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/diagnose/fringe/extra_cause.h"
#include "ramtk/diagnose/fringe/fringe.h"
#include "ramtk/diagnose/fringe/fringe_hidden.h"

namespace ramtk::diagnose {
namespace {

// Phase step k of a pixel gains c·B·cos φ·cos 2δ_k (DN): a ripple no table cause has (projector
// harmonics follow cos 2(φ + δ_k), a frame's gain or offset does not follow φ).
const FringeLinearCause& PhaseCoupledRipple() {
  static const FringeLinearCause cause = [] {
    FringeLinearCause c;
    c.info = {"test_phase_coupled_ripple", DataKind::kFringe, "phase steps ripple with cos φ·cos 2δ (test-only)", "c",
              "none"};
    c.keys = {"c"};
    c.basis = [](const FringeSequenceView& s, const FringePixelView& p, Eigen::Ref<Eigen::MatrixXd> m) {
      for (size_t k = 0; k < s.phase_frame.size(); ++k)
        m(s.phase_frame[k], 0) = p.b * std::cos(p.phi) * std::cos(2.0 * s.step_shift_rad[k]);
    };
    // B and φ of every pixel from the rendered phase frames (N-step formulas), then the ripple.
    c.plant = [](const FringeSequenceView& s, double magnitude, std::vector<cv::Mat>* frames) {
      const int n = static_cast<int>(s.phase_frame.size());
      const cv::Mat& f0 = (*frames)[s.phase_frame[0]];
      for (int y = 0; y < f0.rows; ++y)
        for (int x = 0; x < f0.cols; ++x) {
          double re = 0, im = 0;
          for (int k = 0; k < n; ++k) {
            const double v = (*frames)[s.phase_frame[k]].at<float>(y, x);
            re += v * std::cos(s.step_shift_rad[k]), im -= v * std::sin(s.step_shift_rad[k]);
          }
          const double b = 2.0 / n * std::hypot(re, im), phi = std::atan2(im, re);
          for (int k = 0; k < n; ++k)
            (*frames)[s.phase_frame[k]].at<float>(y, x) +=
                static_cast<float>(magnitude * b * std::cos(phi) * std::cos(2.0 * s.step_shift_rad[k]));
        }
    };
    return c;
  }();
  return cause;
}

Diagnosis DiagnoseSet(const HiddenFringeSet& set) {
  return DiagnoseFringeFrames(set.manifest, set.frames, set.full_scale, DiagnoseOptions{}, "hidden draw");
}

TEST(FringeExtension, ARegisteredCauseIsPlantedNamedAndRecovered) {
  RegisterFringeCause(PhaseCoupledRipple());
  EXPECT_TRUE(IsKnownCause("test_phase_coupled_ripple"));
  HiddenFringeDraw draw;
  draw.seed = 17, draw.effect = draw.expected = "test_phase_coupled_ripple", draw.magnitude = 0.05;
  const Diagnosis d = DiagnoseSet(SimulateHiddenFringe(draw));
  EXPECT_EQ(d.cause, "test_phase_coupled_ripple");
  ASSERT_TRUE(d.parameters.count("c"));
  // The per-pixel fit and the saturated or dark pixels bias c by a few per cent.
  EXPECT_NEAR(d.parameters.at("c"), 0.05, 0.1 * 0.05 + 4.0 * d.sigmas.at("c"));
  // The same set without it: the diagnosis does not claim it.
  draw.effect = draw.expected = "none";
  EXPECT_EQ(DiagnoseSet(SimulateHiddenFringe(draw)).cause, "none");
}

TEST(FringeExtension, RegisteringANameTwiceOrAnInvalidCauseIsAnError) {
  FringeLinearCause twice = PhaseCoupledRipple();
  twice.info.name = "saturation";
  EXPECT_THROW(RegisterFringeCause(twice), InputError);
  FringeLinearCause bad = PhaseCoupledRipple();
  bad.info.name = "test_without_basis";
  bad.basis = nullptr;
  EXPECT_THROW(RegisterFringeCause(bad), InputError);
}

}  // namespace
}  // namespace ramtk::diagnose
