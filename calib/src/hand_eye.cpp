#include "ramtk/calib/hand_eye.h"

#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::calib {
namespace {

cv::Mat ToCvR(const Mat3& r) {
  cv::Mat m;
  cv::eigen2cv(r, m);
  return m;
}
cv::Mat ToCvT(const Vec3& t) { return (cv::Mat_<double>(3, 1) << t.x(), t.y(), t.z()); }
Isometry3 FromCv(const cv::Mat& r, const cv::Mat& t) {
  Isometry3 out = Isometry3::Identity();
  Mat3 rr;
  cv::cv2eigen(r, rr);
  out.linear() = rr;
  out.translation() = Vec3(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  return out;
}

}  // namespace

bool CameraFromBoard(const BoardDetection& detection, const cv::Matx33d& camera_matrix,
                     const std::vector<double>& distortion, Isometry3* camera_from_board) {
  if (!detection.found || detection.image_points.size() < 4) return false;
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(detection.object_points, detection.image_points, camera_matrix, distortion, rvec, tvec, false,
                    cv::SOLVEPNP_ITERATIVE)) {
    return false;
  }
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  *camera_from_board = FromCv(r, cv::Mat(tvec));
  return true;
}

std::string HandEyeOptions::Validate() const { return min_poses < 3 ? "min_poses must be at least 3" : ""; }

std::string HandEyeSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "hand-eye (%s): %d poses, RMS rotation %.4f deg, RMS translation %.4f mm, worst %.4f mm (pose %d)",
                method.c_str(), num_poses, rms_rotation_deg, rms_translation_mm, worst_translation_mm, worst_pose);
  return buf;
}

HandEyeResult CalibrateCameraToRobot(const kinematics::RobotModel& model, const std::vector<BoardPoseObservation>& obs,
                                     const HandEyeOptions& options, HandEyeSummary* summary) {
  const std::string bad = options.Validate();
  if (!bad.empty()) throw InputError({"", 0, "HandEyeOptions"}, bad);
  if (static_cast<int>(obs.size()) < options.min_poses) {
    throw InputError({"", 0, "poses"}, std::to_string(obs.size()) + " poses given; at least " +
                                           std::to_string(options.min_poses) + " are needed");
  }
  std::vector<cv::Mat> r_world2cam, t_world2cam, r_base2gripper, t_base2gripper;
  std::vector<Isometry3> flange;
  for (const BoardPoseObservation& o : obs) {
    if (!o.q_controller.allFinite() || !o.camera_from_board.matrix().allFinite()) {
      throw InputError({"", 0, "poses"}, "non-finite joint angle or board pose");
    }
    flange.push_back(kinematics::BaseFromFlange(model, o.q_controller));
    r_world2cam.push_back(ToCvR(o.camera_from_board.linear()));
    t_world2cam.push_back(ToCvT(o.camera_from_board.translation()));
    r_base2gripper.push_back(ToCvR(flange.back().linear()));
    t_base2gripper.push_back(ToCvT(flange.back().translation()));
  }
  cv::Mat r_board_from_flange, t_board_from_flange, r_cam_from_base, t_cam_from_base;
  cv::calibrateRobotWorldHandEye(
      r_world2cam, t_world2cam, r_base2gripper, t_base2gripper, r_board_from_flange, t_board_from_flange,
      r_cam_from_base, t_cam_from_base,
      options.method == HandEyeMethod::kShah ? cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH : cv::CALIB_ROBOT_WORLD_HAND_EYE_LI);
  HandEyeResult r;
  r.camera_from_base = FromCv(r_cam_from_base, t_cam_from_base);
  r.flange_from_board = FromCv(r_board_from_flange, t_board_from_flange).inverse();
  HandEyeSummary s;
  s.method = options.method == HandEyeMethod::kShah ? "shah" : "li";
  s.num_poses = static_cast<int>(obs.size());
  double sr = 0.0, st = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Isometry3 pred = r.camera_from_base * flange[i] * r.flange_from_board;
    const double dr = RotationAngleBetween(pred.linear(), obs[i].camera_from_board.linear());
    const double dt = (pred.translation() - obs[i].camera_from_board.translation()).norm();
    r.rotation_residual_rad.push_back(dr);
    r.translation_residual_mm.push_back(dt);
    sr += dr * dr;
    st += dt * dt;
    if (dt >= s.worst_translation_mm) s.worst_translation_mm = dt, s.worst_pose = static_cast<int>(i);
  }
  s.rms_rotation_deg = RadToDeg(std::sqrt(sr / obs.size()));
  s.rms_translation_mm = std::sqrt(st / obs.size());
  if (summary) *summary = s;
  return r;
}

}  // namespace ramtk::calib
