// `ramtk diagnose` for fringe image sets: the measured intensities of one camera against the ideal
// fringe model I = A + B·cos(φ + δ_k) (A, B, φ fitted per pixel from the phase-shift frames; the
// Gray-code frames predicted as A ± B from the unwrapped coordinate, through the camera's sampling
// kernel at code edges). Candidates: the rows of the fringe cause table
// (ramtk/diagnose/engine/fringe_causes.def) with a fit; ambient_light and lens_distortion_unmodelled
// leave this model exact and are reported as "none" by design (docs/diagnose_fringe.md).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnose.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::diagnose {

// options.data: a fringe manifest (one phase_shift block and one gray_code block). The camera is
// "left" if present, else the first; `--with camera=NAME` picks another; `--with fill_factor=F` and
// `--with psf_sigma_px=S` state the camera's sampling kernel (box of side F camera px, 0 = point
// sampling, default 1, ⊗ a Gaussian PSF of S camera px, default 0). options.noise > 0 replaces
// the noise floor estimated from the data (differences of the residual between neighbouring pixels
// along the fringes).
Diagnosis DiagnoseFringe(const DiagnoseOptions& options);

// The same analysis on frames already in memory (CV_32FC1 or CV_8U/16U, the manifest's order);
// `label` is recorded as Diagnosis::data. options.data is not read.
Diagnosis DiagnoseFringeFrames(const vision::FringeManifest& manifest, const std::vector<cv::Mat>& frames,
                               double full_scale, const DiagnoseOptions& options, const std::string& label);

}  // namespace ramtk::diagnose
