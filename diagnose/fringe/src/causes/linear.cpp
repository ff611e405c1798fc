// The linear extensions of the ideal fringe model: first-order corrections of the residual,
// projected like the per-pixel fit projects the data (the per-pixel A, B, φ absorb whatever lies in
// the span of 1, cos δ_k, sin δ_k over the phase frames).
#include <algorithm>
#include <cmath>

#include "../fringe_fit_kit.h"

namespace ramtk::diagnose::fringe {

// projector_nonlinearity: harmonics h = 2..H of a memoryless response, B_h/B_1 = r_h. Phase frames
// gain B·cos(hθ_k); Gray frames the response's white/black levels B·Σr_h and B·Σ(−1)^h r_h.
CandidateFit FitProjectorNonlinearity(const CandidateContext& ctx) {
  const FringeFit& fit = *ctx.fit;
  const int n = fit.steps;
  const int hmax = std::max(2, (n + 1) / 2 - 1);  // the harmonics an N-step block resolves
  const int nh = hmax - 1;
  return FitLinear(
      ctx, "projector_nonlinearity", nh,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int c = 0; c < nh; ++c) {
          const int hh = c + 2;
          for (int k = 0; k < n; ++k) mat(ft.phase_frame[k], c) = p.b * std::cos(hh * (p.phi + StepShift(k, n)));
          double w, sp;
          Footprint(ft.kernel, p, &w, &sp);
          for (int j = 0; j < ft.gray_bits; ++j) {
            const double q = GrayPattern(ft, j, p.u, w, sp);
            mat(ft.gray_frame[j], c) = p.b * (q + (1.0 - q) * (hh % 2 == 0 ? 1.0 : -1.0));
          }
        }
      },
      [](int c) { return "B" + std::to_string(c + 2) + "/B1"; }, [](int, double v) { return v; });
}

// phase_shift_error: step k shifted by ε_k: −B·sin(θ_k)·ε_k.
CandidateFit FitPhaseShiftError(const CandidateContext& ctx) {
  const FringeFit& fit = *ctx.fit;
  const int n = fit.steps;
  return FitLinear(
      ctx, "phase_shift_error", n,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int k = 0; k < n; ++k) mat(ft.phase_frame[k], k) = -p.b * std::sin(p.phi + StepShift(k, n));
      },
      [](int k) { return Numbered("step_", k, "_error_deg"); }, [](int, double v) { return v * 180.0 / kPi; });
}

// intensity_drift: per-frame gain g_f and offset o_f: I_f ≈ (1 + g_f)·ideal + o_f.
CandidateFit FitIntensityDrift(const CandidateContext& ctx) {
  const FringeFit& fit = *ctx.fit;
  const int nf = fit.frames;
  return FitLinear(
      ctx, "intensity_drift", 2 * nf,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int f = 0; f < nf; ++f) {
          mat(f, f) = IdealIntensity(ft, p, f);
          mat(f, nf + f) = 1.0;
        }
      },
      [nf](int i) { return i < nf ? Numbered("gain_frame_", i, "") : Numbered("offset_frame_", i - nf, "_DN"); },
      [](int, double v) { return v; });
}

}  // namespace ramtk::diagnose::fringe
