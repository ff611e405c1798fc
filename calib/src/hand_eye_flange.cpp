#include "ramtk/calib/hand_eye_flange.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "hand_eye_json.h"
#include "pose_noise.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/core/error.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

cv::Mat CvR(const Mat3& r) {
  cv::Mat m;
  cv::eigen2cv(r, m);
  return m;
}
cv::Mat CvT(const Vec3& t) { return (cv::Mat_<double>(3, 1) << t.x(), t.y(), t.z()); }

int CvMethod(EyeInHandMethod m) {
  switch (m) {
    case EyeInHandMethod::kTsai:
      return cv::CALIB_HAND_EYE_TSAI;
    case EyeInHandMethod::kPark:
      return cv::CALIB_HAND_EYE_PARK;
    case EyeInHandMethod::kHoraud:
      return cv::CALIB_HAND_EYE_HORAUD;
    case EyeInHandMethod::kAndreff:
      return cv::CALIB_HAND_EYE_ANDREFF;
    case EyeInHandMethod::kDaniilidis:
      return cv::CALIB_HAND_EYE_DANIILIDIS;
  }
  return cv::CALIB_HAND_EYE_TSAI;
}

// The rotation nearest (Frobenius) to the sum of the given rotations: their chordal mean.
Mat3 ChordalMean(const std::vector<Mat3>& rs) {
  Mat3 sum = Mat3::Zero();
  for (const Mat3& r : rs) sum += r;
  return NearestRotation(sum);
}

}  // namespace

const char* EyeInHandMethodName(EyeInHandMethod method) {
  switch (method) {
    case EyeInHandMethod::kTsai:
      return "tsai";
    case EyeInHandMethod::kPark:
      return "park";
    case EyeInHandMethod::kHoraud:
      return "horaud";
    case EyeInHandMethod::kAndreff:
      return "andreff";
    case EyeInHandMethod::kDaniilidis:
      return "daniilidis";
  }
  return "?";
}

EyeInHandMethod ParseEyeInHandMethod(const std::string& text, const InputLocation& where) {
  for (EyeInHandMethod m : {EyeInHandMethod::kTsai, EyeInHandMethod::kPark, EyeInHandMethod::kHoraud,
                            EyeInHandMethod::kAndreff, EyeInHandMethod::kDaniilidis})
    if (text == EyeInHandMethodName(m)) return m;
  throw InputError(where, "expected tsai, park, horaud, andreff or daniilidis, got '" + text + "'");
}

EyeInHandResult CalibrateCameraOnFlange(const std::vector<FlangeCameraObservation>& obs, EyeInHandMethod method) {
  if (obs.size() < 3)
    throw InputError({"", 0, "poses"}, "hand-eye needs at least 3 poses, got " + std::to_string(obs.size()));
  std::vector<Isometry3> flange;
  for (const FlangeCameraObservation& o : obs) {
    if (!o.base_from_flange.matrix().allFinite() || !o.camera_from_board.matrix().allFinite())
      throw InputError({"", 0, "poses"}, "non-finite flange or board pose");
    flange.push_back(o.base_from_flange);
  }
  CheckRotationsExciteTwoAxes(flange);
  std::vector<cv::Mat> r_g2b, t_g2b, r_t2c, t_t2c;
  for (const FlangeCameraObservation& o : obs) {
    r_g2b.push_back(CvR(o.base_from_flange.linear()));
    t_g2b.push_back(CvT(o.base_from_flange.translation()));
    r_t2c.push_back(CvR(o.camera_from_board.linear()));
    t_t2c.push_back(CvT(o.camera_from_board.translation()));
  }
  cv::Mat r, t;
  try {
    cv::calibrateHandEye(r_g2b, t_g2b, r_t2c, t_t2c, r, t, static_cast<cv::HandEyeCalibrationMethod>(CvMethod(method)));
  } catch (const cv::Exception& e) {
    throw InputError({"", 0, "poses"}, std::string("OpenCV's hand-eye solver failed: ") + e.what());
  }
  EyeInHandResult out;
  Mat3 rr;
  cv::cv2eigen(r, rr);
  out.flange_from_camera.linear() = rr;
  out.flange_from_camera.translation() = Vec3(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  if (!out.flange_from_camera.matrix().allFinite())
    throw InputError({"", 0, "poses"}, std::string("OpenCV's hand-eye solver (") + EyeInHandMethodName(method) +
                                           ") returned no finite solution: the poses may not excite two rotation axes");
  std::vector<Mat3> rs;
  Vec3 tsum = Vec3::Zero();
  for (const FlangeCameraObservation& o : obs) {
    const Isometry3 b = o.base_from_flange * out.flange_from_camera * o.camera_from_board;
    rs.push_back(b.linear());
    tsum += b.translation();
  }
  out.base_from_board.linear() = ChordalMean(rs);
  out.base_from_board.translation() = tsum / static_cast<double>(obs.size());
  double sr = 0, st = 0;
  for (const FlangeCameraObservation& o : obs) {
    const Isometry3 predicted = (o.base_from_flange * out.flange_from_camera).inverse() * out.base_from_board;
    const Isometry3 e = predicted.inverse() * o.camera_from_board;
    const double angle = RadToDeg(Eigen::AngleAxisd(e.linear()).angle());
    const double dist = (o.camera_from_board.translation() - predicted.translation()).norm();
    out.rotation_residual_deg.push_back(angle);
    out.translation_residual_mm.push_back(dist);
    sr += angle * angle;
    st += dist * dist;
  }
  out.rms_rotation_deg = std::sqrt(sr / obs.size());
  out.rms_translation_mm = std::sqrt(st / obs.size());
  return out;
}

std::vector<FlangeCameraObservation> SimulateFlangeCameraPoses(const std::vector<Isometry3>& base_from_flange,
                                                               const Isometry3& flange_from_camera,
                                                               const Isometry3& base_from_board, double sigma_deg,
                                                               double sigma_mm, unsigned seed) {
  internal::RequirePoseNoise(sigma_deg, sigma_mm);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<FlangeCameraObservation> obs;
  for (const Isometry3& bf : base_from_flange) {
    FlangeCameraObservation o;
    o.base_from_flange = bf;
    o.camera_from_board =
        internal::PerturbPose((bf * flange_from_camera).inverse() * base_from_board, sigma_deg, sigma_mm, rng, g);
    obs.push_back(o);
  }
  return obs;
}

std::string EyeInHandResultJson(const EyeInHandResult& result, EyeInHandMethod method,
                                const EyeInHandRefinement* refinement) {
  nlohmann::json j;
  j["setup"] = "camera on the flange (AX = XB)";
  j["method"] = std::string(EyeInHandMethodName(method)) + (refinement ? " + Ceres" : "");
  if (refinement) j["refinement"] = internal::RefinementJson(*refinement, "flange_from_camera", "flange frame");
  j["flange_from_camera"] = PoseToJson(result.flange_from_camera);
  j["base_from_board"] = PoseToJson(result.base_from_board);
  j["rotation_residual_deg"] = result.rotation_residual_deg;
  j["translation_residual_mm"] = result.translation_residual_mm;
  j["rms_rotation_deg"] = result.rms_rotation_deg;
  j["rms_translation_mm"] = result.rms_translation_mm;
  return j.dump(2) + "\n";
}

std::string EyeInHandBriefReport(const EyeInHandResult& result, EyeInHandMethod method,
                                 const EyeInHandRefinement* refinement) {
  const KukaAbc abc = KukaAbcFromRotation(result.flange_from_camera.linear());
  const Vec3 t = result.flange_from_camera.translation();
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "hand-eye, camera on the flange (%s): %zu poses, residual RMS %.4f deg, %.4f mm; flange_from_camera "
                "t (mm) %.4f %.4f %.4f  A,B,C (deg) %.5f %.5f %.5f",
                EyeInHandMethodName(method), result.rotation_residual_deg.size(), result.rms_rotation_deg,
                result.rms_translation_mm, t.x(), t.y(), t.z(), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  std::string out = buf;
  if (refinement) {
    const EyeInHandRefinement& f = *refinement;
    std::snprintf(
        buf, sizeof buf,
        "\nrefined (Ceres, SE(3)): sigma t (mm) %.4f %.4f %.4f, rotation (deg) %.5f %.5f %.5f; noise %s %.4f deg, "
        "%.4f mm per axis",
        f.translation_sigma_mm.x(), f.translation_sigma_mm.y(), f.translation_sigma_mm.z(), f.rotation_sigma_deg.x(),
        f.rotation_sigma_deg.y(), f.rotation_sigma_deg.z(),
        f.pose_covariance ? "per-image covariance; residual RMS" : (f.noise_estimated ? "estimated" : "given"),
        f.sigma_deg, f.sigma_mm);
    out += buf;
    if (f.pose_covariance) {
      std::snprintf(buf, sizeof buf,
                    "\nvariance factor %.3f (chi2 / dof of the weighted residuals); noise beyond the images' "
                    "%.4f deg, %.4f mm per axis",
                    f.variance_factor, f.extra_noise_deg, f.extra_noise_mm);
      out += buf;
    }
  }
  return out;
}

}  // namespace ramtk::calib
