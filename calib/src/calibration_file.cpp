// Stereo / single-camera calibration files: the rig's keys from ramtk::camera's writer, then the
// calibration session's details.
#include <opencv2/core/persistence.hpp>

#include "ramtk/calib/camera_calibration.h"

namespace ramtk::calib {
namespace {

void WriteRejected(cv::FileStorage& fs, const std::string& key, const std::vector<RejectedView>& rejected) {
  fs << key << "[";
  for (const RejectedView& r : rejected)
    fs << "{"
       << "name" << r.name << "reason" << r.reason << "}";
  fs << "]";
}

// One camera's single-camera fit: rms<suffix>, per_view_errors<suffix>, views<suffix>, rejected_views<suffix>.
void WriteSession(cv::FileStorage& fs, const CameraCalibrationResult& c, const std::string& suffix) {
  fs << ("rms" + suffix) << c.rms_px;
  fs << ("per_view_errors" + suffix) << cv::Mat(c.per_view_rms_px, true);
  fs << ("views" + suffix) << "[";
  for (const std::string& n : c.view_names) fs << n;
  fs << "]";
  WriteRejected(fs, "rejected_views" + suffix, c.rejected);
}

// The corner comparison of CalibrateCameraComparingCorners / CalibrateStereoComparingCorners.
void WriteCornerComparison(cv::FileStorage& fs, const CornerComparison& c, int cameras) {
  fs << "corners" << (c.chosen == CornerRefinement::kSubPix ? "subpix" : "sector");
  for (const auto& [name, fit] :
       {std::pair<const char*, const CornerSetFit*>{"subpix", &c.subpix}, {"sector", &c.sector}}) {
    fs << (std::string("corner_views_") + name) << fit->views;
    fs << (std::string("corner_rms_px_") + name) << (fit->ok ? fit->rms_px : -1.0);
    fs << (std::string("corner_fx_sigma_px_") + name) << "[";
    for (int i = 0; i < cameras; ++i) fs << (fit->ok ? fit->fx_sigma_px[i] : -1.0);
    fs << "]";
  }
}

}  // namespace

std::string StereoCalibrationYaml(const StereoCalibrationResult& st, const BoardSpec& board,
                                  const CornerComparison* corners, camera::CalibrationFormat format) {
  return camera::StereoCalibrationText(st.rig, format,
                                       "ramtk stereo calibration: x_right = R * x_left + T (mm); parameter_std order " +
                                           std::string(camera::kCalibParameterStdOrder),
                                       [&](cv::FileStorage& fs) {
                                         fs << "board" << board.ToString();
                                         WriteSession(fs, st.left, "1");
                                         WriteSession(fs, st.right, "2");
                                         WriteRejected(fs, "rejected_pairs", st.rejected_pairs);
                                         if (corners) WriteCornerComparison(fs, *corners, 2);
                                       });
}

std::string CameraCalibrationYaml(const CameraCalibrationResult& camera, const BoardSpec& board,
                                  const CornerComparison* corners, camera::CalibrationFormat format) {
  return camera::CameraCalibrationText(
      camera.intrinsics, camera.rms_px, camera.per_view_rms_px, camera.std_intrinsics,
      camera.intrinsics.distortion.model == camera::LensModel::kPinhole5
          ? "ramtk single-camera calibration; parameter_std order fx fy cx cy k1 k2 p1 p2 k3"
          : "ramtk single-camera calibration; parameter_std order fx fy cx cy, then D1's coefficients",
      [&](cv::FileStorage& fs) {
        fs << "board" << board.ToString();
        fs << "views1"
           << "[";
        for (const std::string& n : camera.view_names) fs << n;
        fs << "]";
        WriteRejected(fs, "rejected_views1", camera.rejected);
        if (corners) WriteCornerComparison(fs, *corners, 1);
      },
      format);
}

}  // namespace ramtk::calib
