// Calibrating a session from both chessboard corner sets and keeping one (CornerChoice).
#include <cstdio>

#include "ramtk/calib/camera_calibration.h"
#include "ramtk/core/error.h"

namespace ramtk::calib {
namespace {

// Picks the kept set; InputError if it cannot be calibrated.
bool KeepSubPix(CornerChoice choice, const CornerSetFit& subpix, const CornerSetFit& sector) {
  if (choice == CornerChoice::kLowerRms) {
    if (!subpix.ok && !sector.ok) throw InputError({"", 0, "views"}, subpix.error);
    if (!subpix.ok || !sector.ok) return subpix.ok;
    return subpix.rms_px <= sector.rms_px;
  }
  const bool keep_subpix = choice == CornerChoice::kSubPix;
  const CornerSetFit& kept = keep_subpix ? subpix : sector;
  if (!kept.ok) throw InputError({"", 0, "views"}, kept.error);
  return keep_subpix;
}

// Calibrates from both sets (`calibrate(use_subpix, summary)`), records each one's figures
// (`describe`) or its failure, and returns the kept set's result.
template <typename Result, typename Calibrate, typename Describe>
Result Compare(Calibrate&& calibrate, Describe&& describe, CornerChoice choice, CameraCalibrationSummary* summary,
               CornerComparison* comparison) {
  CornerComparison c;
  Result results[2];
  CameraCalibrationSummary summaries[2];
  for (const bool use_subpix : {true, false}) {
    const int i = use_subpix ? 0 : 1;
    CornerSetFit& fit = use_subpix ? c.subpix : c.sector;
    try {
      results[i] = calibrate(use_subpix, &summaries[i]);
      fit.ok = true;
      describe(results[i], &fit);
    } catch (const InputError& e) {
      fit.error = e.message();  // reported in the comparison; KeepSubPix throws if this set is the one kept
    }
  }
  const int kept = KeepSubPix(choice, c.subpix, c.sector) ? 0 : 1;
  c.chosen = kept == 0 ? CornerRefinement::kSubPix : CornerRefinement::kSectorBased;
  if (summary) *summary = summaries[kept];
  if (comparison) *comparison = c;
  return results[kept];
}

}  // namespace

CornerChoice ParseCornerChoice(const std::string& text, const InputLocation& where) {
  if (text == "subpix") return CornerChoice::kSubPix;
  if (text == "sector") return CornerChoice::kSectorBased;
  if (text == "auto") return CornerChoice::kLowerRms;
  throw InputError(where, "expected subpix, sector or auto, got '" + text + "'");
}

std::string CornerComparison::BriefReport() const {
  auto one = [](const char* name, const CornerSetFit& f) {
    char buf[200];
    if (!f.ok) {
      std::snprintf(buf, sizeof buf, "%s corners: failed (%s)", name, f.error.c_str());
    } else if (f.fx_sigma_px[1] > 0) {
      std::snprintf(buf, sizeof buf, "%s corners: %d pairs, stereo RMS %.4f px, sigma fx %.3f / %.3f px", name, f.views,
                    f.rms_px, f.fx_sigma_px[0], f.fx_sigma_px[1]);
    } else {
      std::snprintf(buf, sizeof buf, "%s corners: %d views, RMS %.4f px, sigma fx %.3f px", name, f.views, f.rms_px,
                    f.fx_sigma_px[0]);
    }
    return std::string(buf);
  };
  return one("refined (subpix)", subpix) + "; " + one("sector-based", sector) + "; kept " +
         (chosen == CornerRefinement::kSubPix ? "subpix" : "sector");
}

CameraCalibrationResult CalibrateCameraComparingCorners(const std::vector<ViewPoints>& subpix,
                                                        const std::vector<ViewPoints>& sector, cv::Size image_size,
                                                        const CameraCalibrationOptions& options, CornerChoice choice,
                                                        CameraCalibrationSummary* summary,
                                                        CornerComparison* comparison) {
  return Compare<CameraCalibrationResult>(
      [&](bool use_subpix, CameraCalibrationSummary* s) {
        return CalibrateCamera(use_subpix ? subpix : sector, image_size, options, s);
      },
      [](const CameraCalibrationResult& r, CornerSetFit* f) {
        f->views = static_cast<int>(r.view_names.size());
        f->rms_px = r.rms_px;
        f->fx_sigma_px[0] = r.std_intrinsics.empty() ? 0.0 : r.std_intrinsics[0];
      },
      choice, summary, comparison);
}

StereoCalibrationResult CalibrateStereoComparingCorners(const std::vector<ViewPoints>& left_subpix,
                                                        const std::vector<ViewPoints>& right_subpix,
                                                        const std::vector<ViewPoints>& left_sector,
                                                        const std::vector<ViewPoints>& right_sector,
                                                        cv::Size image_size, const CameraCalibrationOptions& options,
                                                        CornerChoice choice, CameraCalibrationSummary* summary,
                                                        CornerComparison* comparison) {
  return Compare<StereoCalibrationResult>(
      [&](bool use_subpix, CameraCalibrationSummary* s) {
        return use_subpix ? CalibrateStereo(left_subpix, right_subpix, image_size, options, s)
                          : CalibrateStereo(left_sector, right_sector, image_size, options, s);
      },
      [](const StereoCalibrationResult& r, CornerSetFit* f) {
        f->views = static_cast<int>(r.pair_names.size());
        f->rms_px = r.rig.rms_px;
        if (r.rig.parameter_std.size() >= 10) {
          f->fx_sigma_px[0] = r.rig.parameter_std[0];
          f->fx_sigma_px[1] = r.rig.parameter_std[9];
        }
      },
      choice, summary, comparison);
}

}  // namespace ramtk::calib
