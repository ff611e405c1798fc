#pragma once
// Least-squares N-step phase shifting. Model per pixel: I_k = A + B*cos(phi + 2*pi*k/N),
// k = 0..N-1, N >= 3. The LS solution is phi = atan2(-S, C), B = 2/N*sqrt(S^2 + C^2),
// A = mean(I_k), with S = sum I_k sin(d_k), C = sum I_k cos(d_k).
// Phase noise from intensity noise sigma_I: sigma_phi = sqrt(2/N) * sigma_I / B.

#include <opencv2/core.hpp>
#include <vector>

namespace ramtk::vision {

struct PhaseShiftResult {
  cv::Mat wrapped;      // CV_32F, phi in [-pi, pi)
  cv::Mat background;   // CV_32F, A (DN)
  cv::Mat modulation;   // CV_32F, B (DN)
  cv::Mat residual_ss;  // CV_32F, sum of squared fit residuals (DN^2); 0 for N = 3
  cv::Mat max_sample;   // CV_32F, brightest of the N samples (DN)
  int steps = 0;
};

// `frames` holds the N phase-shifted images (CV_32FC1, same size). Rows run in parallel.
PhaseShiftResult ComputePhaseShift(const std::vector<cv::Mat>& frames);

// sqrt(2/N) * sigma_intensity / B per pixel (CV_32F), +inf where B <= 0.
cv::Mat PhaseSigma(const cv::Mat& modulation, int steps, double sigma_intensity);

}  // namespace ramtk::vision
