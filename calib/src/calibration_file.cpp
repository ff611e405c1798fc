// Stereo / single-camera calibration files: OpenCV FileStorage YAML with the standard keys.
#include <opencv2/core/persistence.hpp>

#include "ramtk/calib/camera_calibration.h"

namespace ramtk::calib {
namespace {

void WriteCamera(cv::FileStorage& fs, const CameraCalibrationResult& c, const std::string& suffix) {
  fs << ("K" + suffix) << cv::Mat(c.camera_matrix);
  fs << ("D" + suffix) << cv::Mat(c.distortion, true).reshape(1, 1);
  fs << ("std_intrinsics" + suffix) << cv::Mat(c.std_intrinsics, true).reshape(1, 1);
  fs << ("rms" + suffix) << c.rms_px;
  fs << ("per_view_errors" + suffix) << cv::Mat(c.per_view_rms_px, true);
  fs << ("views" + suffix) << "[";
  for (const std::string& n : c.view_names) fs << n;
  fs << "]";
  fs << ("rejected_views" + suffix) << "[";
  for (const RejectedView& r : c.rejected)
    fs << "{"
       << "name" << r.name << "reason" << r.reason << "}";
  fs << "]";
}

}  // namespace

std::string StereoCalibrationYaml(const StereoCalibrationResult& st, const BoardSpec& board) {
  cv::FileStorage fs("calibration.yml",
                     cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs.writeComment(
      "ramtk stereo calibration: x_right = R * x_left + T (mm); std_intrinsics order fx fy cx cy k1 k2 p1 p2 k3");
  fs << "image_size" << st.left.image_size;
  fs << "board" << board.ToString();
  WriteCamera(fs, st.left, "1");
  WriteCamera(fs, st.right, "2");
  fs << "R" << cv::Mat(st.rotation);
  fs << "T" << cv::Mat(st.translation);
  fs << "std_R" << cv::Mat(cv::Vec3d(st.std_rt[0], st.std_rt[1], st.std_rt[2])).reshape(1, 1);  // rotation vector, rad
  fs << "std_T" << cv::Mat(cv::Vec3d(st.std_rt[3], st.std_rt[4], st.std_rt[5])).reshape(1, 1);  // mm
  fs << "rms" << st.rms_px;
  cv::Mat per_pair(static_cast<int>(st.per_pair_rms_px.size()), 2, CV_64F);
  for (int i = 0; i < per_pair.rows; ++i) {
    per_pair.at<double>(i, 0) = st.per_pair_rms_px[i][0];
    per_pair.at<double>(i, 1) = st.per_pair_rms_px[i][1];
  }
  fs << "per_view_errors" << per_pair;
  fs << "rejected_pairs"
     << "[";
  for (const RejectedView& r : st.rejected_pairs)
    fs << "{"
       << "name" << r.name << "reason" << r.reason << "}";
  fs << "]";
  return fs.releaseAndGetString();
}

std::string CameraCalibrationYaml(const CameraCalibrationResult& camera, const BoardSpec& board) {
  cv::FileStorage fs("calibration.yml",
                     cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs.writeComment("ramtk single-camera calibration; std_intrinsics order fx fy cx cy k1 k2 p1 p2 k3");
  fs << "image_size" << camera.image_size;
  fs << "board" << board.ToString();
  WriteCamera(fs, camera, "1");
  return fs.releaseAndGetString();
}

}  // namespace ramtk::calib
