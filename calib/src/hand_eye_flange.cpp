#include "ramtk/calib/hand_eye_flange.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "pose_noise.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/core/csv.h"
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

std::vector<FlangeCameraObservation> ReadFlangeCameraObservations(const std::string& path,
                                                                  const std::string& flange_units) {
  double scale = 1.0;
  if (flange_units == "m") {
    scale = 1000.0;
  } else if (flange_units != "mm") {
    throw InputError({path, 0, "flange_units"}, "expected 'mm' or 'm', got '" + flange_units + "'");
  }
  const CsvTable t = ReadCsv(path);
  const int x = t.Column("x"), y = t.Column("y"), z = t.Column("z");
  const int a = t.Column("a"), b = t.Column("b"), c = t.Column("c");
  const bool matrix = t.Column("flange_m00", false) >= 0;
  const bool quaternion = !matrix && t.Column("flange_qw", false) >= 0;
  int m[12] = {0};
  int fx = -1, fy = -1, fz = -1, fa = -1, fb = -1, fc = -1, qw = -1, qx = -1, qy = -1, qz = -1;
  if (matrix) {
    for (int i = 0; i < 12; ++i) m[i] = t.Column("flange_m" + std::to_string(i / 4) + std::to_string(i % 4));
  } else {
    fx = t.Column("flange_x"), fy = t.Column("flange_y"), fz = t.Column("flange_z");
    if (quaternion) {
      qw = t.Column("flange_qw"), qx = t.Column("flange_qx"), qy = t.Column("flange_qy"), qz = t.Column("flange_qz");
    } else {
      fa = t.Column("flange_a"), fb = t.Column("flange_b"), fc = t.Column("flange_c");
    }
  }
  std::vector<FlangeCameraObservation> obs;
  for (std::size_t r = 0; r < t.size(); ++r) {
    FlangeCameraObservation o;
    o.camera_from_board.translation() = Vec3(t.Number(r, x), t.Number(r, y), t.Number(r, z));
    o.camera_from_board.linear() =
        RotationFromKukaAbc({DegToRad(t.Number(r, a)), DegToRad(t.Number(r, b)), DegToRad(t.Number(r, c))});
    if (matrix) {
      Mat3 rot;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rot(i, j) = t.Number(r, m[i * 4 + j]);
      const double orth = (rot.transpose() * rot - Mat3::Identity()).cwiseAbs().maxCoeff();
      if (orth > 1e-6 || rot.determinant() < 0)
        throw InputError({path, t.line_numbers[r], "flange_m00..flange_m22"},
                         "the rotation part is not a rotation (max |R^T R - I| = " + std::to_string(orth) + ")");
      o.base_from_flange.linear() = rot;
      o.base_from_flange.translation() = scale * Vec3(t.Number(r, m[3]), t.Number(r, m[7]), t.Number(r, m[11]));
    } else {
      o.base_from_flange.translation() = scale * Vec3(t.Number(r, fx), t.Number(r, fy), t.Number(r, fz));
      if (quaternion) {
        Eigen::Quaterniond q(t.Number(r, qw), t.Number(r, qx), t.Number(r, qy), t.Number(r, qz));
        if (std::abs(q.norm() - 1.0) > 1e-3)
          throw InputError({path, t.line_numbers[r], "flange_qw..flange_qz"},
                           "the quaternion's norm is " + std::to_string(q.norm()) + ", expected 1 (within 1e-3)");
        o.base_from_flange.linear() = q.normalized().toRotationMatrix();
      } else {
        o.base_from_flange.linear() =
            RotationFromKukaAbc({DegToRad(t.Number(r, fa)), DegToRad(t.Number(r, fb)), DegToRad(t.Number(r, fc))});
      }
    }
    obs.push_back(o);
  }
  return obs;
}

std::string FormatFlangeCameraObservations(const std::vector<FlangeCameraObservation>& obs) {
  const std::vector<std::string> header = {
      "pose", "flange_x", "flange_y", "flange_z", "flange_a", "flange_b", "flange_c", "x", "y", "z", "a", "b", "c"};
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    std::vector<std::string> row = {std::to_string(i + 1)};
    for (const Isometry3* p : {&obs[i].base_from_flange, &obs[i].camera_from_board}) {
      for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(p->translation()[k], 6));
      const KukaAbc abc = KukaAbcFromRotation(p->linear());
      for (double v : {abc.a, abc.b, abc.c}) row.push_back(FormatFixed(RadToDeg(v), 9));
    }
    rows.push_back(row);
  }
  return FormatCsv(header, rows);
}

std::string EyeInHandResultJson(const EyeInHandResult& result, EyeInHandMethod method,
                                const EyeInHandRefinement* refinement) {
  nlohmann::json j;
  j["setup"] = "camera on the flange (AX = XB)";
  j["method"] = std::string(EyeInHandMethodName(method)) + (refinement ? " + Ceres" : "");
  if (refinement) {
    const EyeInHandRefinement& f = *refinement;
    nlohmann::json cov = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) {
      nlohmann::json row = nlohmann::json::array();
      for (int k = 0; k < 6; ++k) row.push_back(f.flange_from_camera_covariance(i, k));
      cov.push_back(row);
    }
    j["refinement"] = {
        {"converged", f.converged},
        {"iterations", f.iterations},
        {"noise_sigma_deg", f.sigma_deg},
        {"noise_sigma_mm", f.sigma_mm},
        {"noise_estimated_from_residuals", f.noise_estimated},
        {"flange_from_camera_rotation_sigma_deg",
         {f.rotation_sigma_deg.x(), f.rotation_sigma_deg.y(), f.rotation_sigma_deg.z()}},
        {"flange_from_camera_translation_sigma_mm",
         {f.translation_sigma_mm.x(), f.translation_sigma_mm.y(), f.translation_sigma_mm.z()}},
        {"flange_from_camera_covariance", cov},
        {"covariance_order", "rotation vector (rad, flange frame, left perturbation), translation (mm)"}};
  }
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
        f.rotation_sigma_deg.y(), f.rotation_sigma_deg.z(), f.noise_estimated ? "estimated" : "given", f.sigma_deg,
        f.sigma_mm);
    out += buf;
  }
  return out;
}

}  // namespace ramtk::calib
