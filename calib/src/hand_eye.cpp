#include "ramtk/calib/hand_eye.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "ramtk/calib/hand_eye_flange_refine.h"
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

// Per-pose residuals of `r` (measured vs predicted camera_from_board) and their statistics.
void SummarizeResiduals(const std::vector<StandCameraObservation>& obs, HandEyeResult* r, HandEyeSummary* s) {
  s->num_poses = static_cast<int>(obs.size());
  s->worst_translation_mm = 0.0;
  s->worst_pose = -1;
  r->rotation_residual_rad.clear();
  r->translation_residual_mm.clear();
  double sr = 0.0, st = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Isometry3 pred = r->camera_from_base * obs[i].base_from_flange * r->flange_from_board;
    const double dr = RotationAngleBetween(pred.linear(), obs[i].camera_from_board.linear());
    const double dt = (pred.translation() - obs[i].camera_from_board.translation()).norm();
    r->rotation_residual_rad.push_back(dr);
    r->translation_residual_mm.push_back(dt);
    sr += dr * dr;
    st += dt * dt;
    if (dt >= s->worst_translation_mm) s->worst_translation_mm = dt, s->worst_pose = static_cast<int>(i);
  }
  s->rms_rotation_deg = RadToDeg(std::sqrt(sr / obs.size()));
  s->rms_translation_mm = std::sqrt(st / obs.size());
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

std::string HandEyeOptions::Validate() const {
  if (min_poses < 3) return "min_poses must be at least 3";
  return "";
}

std::string HandEyeSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "hand-eye (%s%s): %d poses, RMS rotation %.4f deg, RMS translation %.4f mm, worst %.4f mm (index %d)",
                method.c_str(), refined ? " + Ceres" : "", num_poses, rms_rotation_deg, rms_translation_mm,
                worst_translation_mm, worst_pose);
  return buf;
}

HandEyeResult CalibrateCameraToRobot(const kinematics::RobotModel& model, const std::vector<BoardPoseObservation>& obs,
                                     const HandEyeOptions& options, HandEyeSummary* summary) {
  std::vector<StandCameraObservation> flange_obs;
  for (const BoardPoseObservation& o : obs) {
    if (!o.q_controller.allFinite()) throw InputError({"", 0, "poses"}, "non-finite joint angle");
    flange_obs.push_back({kinematics::BaseFromFlange(model, o.q_controller), o.camera_from_board});
  }
  return CalibrateStandCamera(flange_obs, options, summary);
}

void CheckRotationsExciteTwoAxes(const std::vector<Isometry3>& flange) {
  // The rotation part is observable only from rotations about at least two different axes; with
  // fewer, OpenCV's closed forms divide by zero (a "determinant is null" exception).
  {
    std::vector<Vec3> axes;
    double largest_deg = 0.0;
    for (std::size_t i = 1; i < flange.size(); ++i) {
      const Eigen::AngleAxisd rel(flange[0].linear().transpose() * flange[i].linear());
      largest_deg = std::max(largest_deg, RadToDeg(rel.angle()));
      if (RadToDeg(rel.angle()) > 1.0) axes.push_back(rel.axis());
    }
    bool two_axes = false;
    for (std::size_t i = 0; i < axes.size() && !two_axes; ++i)
      for (std::size_t j = i + 1; j < axes.size() && !two_axes; ++j)
        two_axes = std::abs(axes[i].dot(axes[j])) < std::cos(DegToRad(5.0));
    if (!two_axes) {
      throw InputError({"", 0, "poses"},
                       "the flange orientations do not vary enough (largest rotation from the first "
                       "pose " +
                           std::to_string(largest_deg) +
                           " deg): hand-eye needs rotations "
                           "of more than 1 deg about at least two axes 5 deg apart");
    }
  }
}

HandEyeResult CalibrateStandCamera(const std::vector<StandCameraObservation>& obs, const HandEyeOptions& options,
                                   HandEyeSummary* summary) {
  ThrowIfInvalid(options.Validate(), "HandEyeOptions");
  if (options.refine) return CalibrateStandCameraWithCovariance(obs, options, {}, summary);
  if (static_cast<int>(obs.size()) < options.min_poses) {
    throw InputError({"", 0, "poses"}, std::to_string(obs.size()) + " poses given; at least " +
                                           std::to_string(options.min_poses) + " are needed");
  }
  std::vector<cv::Mat> r_world2cam, t_world2cam, r_base2gripper, t_base2gripper;
  std::vector<Isometry3> flange;
  for (const StandCameraObservation& o : obs) {
    if (!o.base_from_flange.matrix().allFinite() || !o.camera_from_board.matrix().allFinite()) {
      throw InputError({"", 0, "poses"}, "non-finite flange or board pose");
    }
    flange.push_back(o.base_from_flange);
    r_world2cam.push_back(ToCvR(o.camera_from_board.linear()));
    t_world2cam.push_back(ToCvT(o.camera_from_board.translation()));
    r_base2gripper.push_back(ToCvR(flange.back().linear()));
    t_base2gripper.push_back(ToCvT(flange.back().translation()));
  }
  CheckRotationsExciteTwoAxes(flange);
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
  SummarizeResiduals(obs, &r, &s);
  if (summary) *summary = s;
  return r;
}

HandEyeResult CalibrateStandCameraWithCovariance(const std::vector<StandCameraObservation>& obs,
                                                 const HandEyeOptions& options,
                                                 const EyeInHandRefineOptions& refine_options, HandEyeSummary* summary,
                                                 EyeInHandRefinement* refinement) {
  HandEyeOptions closed_form = options;
  closed_form.refine = false;
  HandEyeSummary s;
  HandEyeResult r = RefineStandCamera(obs, CalibrateStandCamera(obs, closed_form, &s), refine_options, refinement);
  s.refined = true;
  if (refinement) {
    s.iterations = refinement->iterations;
    s.initial_cost = refinement->initial_cost;
    s.final_cost = refinement->final_cost;
  }
  SummarizeResiduals(obs, &r, &s);
  if (summary) *summary = s;
  return r;
}

}  // namespace ramtk::calib
