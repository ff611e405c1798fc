#include "ramtk/calib/board_pose.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

cv::Vec3d RvecOf(const Mat3& r) {
  cv::Matx33d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
  cv::Vec3d v;
  cv::Rodrigues(m, v);
  return v;
}

Isometry3 PoseOf(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d m;
  cv::Rodrigues(rvec, m);
  Isometry3 p = Isometry3::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = m(i, j);
    p.translation()[i] = tvec[i];
  }
  return p;
}

// d rvec / d ω of rvec(exp(ω)·R) at ω = 0, by central differences (Rodrigues is smooth away from
// a half turn; the step leaves ~1e-10 relative error).
Mat3 RvecFromLeftRotation(const Mat3& r) {
  Mat3 d;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Vec3 w = Vec3::Zero();
    w[k] = h;
    const cv::Vec3d plus = RvecOf(Eigen::AngleAxisd(h, w.normalized()).toRotationMatrix() * r);
    const cv::Vec3d minus = RvecOf(Eigen::AngleAxisd(-h, w.normalized()).toRotationMatrix() * r);
    for (int i = 0; i < 3; ++i) d(i, k) = (plus[i] - minus[i]) / (2 * h);
  }
  return d;
}

// Projections and OpenCV's Jacobian (2n × (10 + distortion count)): rvec, tvec, fx fy, cx cy, dist.
Eigen::MatrixXd ProjectionJacobian(const camera::CameraIntrinsics& camera, const std::vector<cv::Point3f>& points,
                                   const Isometry3& pose, std::vector<cv::Point2f>* projected) {
  std::vector<cv::Point2f> p;
  cv::Mat jac;
  const cv::Vec3d t(pose.translation().x(), pose.translation().y(), pose.translation().z());
  cv::projectPoints(points, RvecOf(pose.linear()), t, camera::CameraMatrix(camera),
                    camera::DistortionCoefficients(camera), p, jac);
  if (projected) *projected = p;
  Eigen::MatrixXd j(jac.rows, jac.cols);
  for (int r = 0; r < jac.rows; ++r)
    for (int c = 0; c < jac.cols; ++c) j(r, c) = jac.at<double>(r, c);
  return j;
}

// The pose columns of a projection Jacobian in the [ω; δt] parametrization.
Eigen::MatrixXd PoseColumns(const Eigen::MatrixXd& j, const Mat3& rotation) {
  Eigen::MatrixXd out(j.rows(), 6);
  out.leftCols<3>() = j.leftCols<3>() * RvecFromLeftRotation(rotation);
  out.rightCols<3>() = j.middleCols<3>(3);
  return out;
}

double SquaredResidual(const std::vector<cv::Point2f>& measured, const std::vector<cv::Point2f>& projected) {
  double ss = 0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const double dx = measured[i].x - projected[i].x, dy = measured[i].y - projected[i].y;
    ss += dx * dx + dy * dy;
  }
  return ss;
}

Mat6 InverseOrZero(const Mat6& information) {
  const Eigen::FullPivLU<Mat6> lu(information);
  if (!lu.isInvertible()) return Mat6::Zero();
  return lu.inverse();
}

}  // namespace

std::string BoardPoseOptions::Validate() const {
  if (min_points < 4) return "min_points must be >= 4 (a pose needs four points)";
  if (!(sigma_px >= 0) || !std::isfinite(sigma_px)) return "sigma_px must be >= 0 (0: estimated)";
  return "";
}

std::string BoardPoseSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << "board poses: " << used << " of " << views << " views, reprojection RMS " << rms_px << " px, corner sigma "
    << sigma_px << " px (" << (sigma_estimated ? "from the residuals" : "given") << ")";
  if (!skipped.empty()) s << ", " << skipped.size() << " skipped";
  return s.str();
}

Eigen::MatrixXd BoardPoseJacobian(const camera::CameraIntrinsics& camera, const std::vector<cv::Point3f>& object_points,
                                  const Isometry3& camera_from_board) {
  return PoseColumns(ProjectionJacobian(camera, object_points, camera_from_board, nullptr),
                     camera_from_board.linear());
}

std::vector<BoardPoseEstimate> EstimateBoardPoses(const std::vector<ViewPoints>& views,
                                                  const camera::CameraIntrinsics& camera,
                                                  const BoardPoseOptions& options, BoardPoseSummary* summary) {
  ThrowIfInvalid(options.Validate(), "BoardPoseOptions");
  BoardPoseSummary s;
  s.views = static_cast<int>(views.size());
  std::vector<BoardPoseEstimate> out;
  std::vector<Mat6> information;  // JᵀJ per kept view
  double ss = 0;
  long long n = 0;
  for (const ViewPoints& v : views) {
    if (static_cast<int>(v.image_points.size()) < options.min_points) {
      s.skipped.push_back({v.name, v.image_points.empty() ? "board not found"
                                                          : std::to_string(v.image_points.size()) +
                                                                " features, fewer than " +
                                                                std::to_string(options.min_points)});
      continue;
    }
    cv::Vec3d rvec, tvec;
    bool ok = false;
    try {
      ok = cv::solvePnP(v.object_points, v.image_points, camera::CameraMatrix(camera),
                        camera::DistortionCoefficients(camera), rvec, tvec, false, cv::SOLVEPNP_IPPE);
      if (ok)
        cv::solvePnPRefineLM(v.object_points, v.image_points, camera::CameraMatrix(camera),
                             camera::DistortionCoefficients(camera), rvec, tvec,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-12));
    } catch (const cv::Exception& e) {
      ok = false;
    }
    if (!ok || !std::isfinite(cv::norm(rvec)) || !std::isfinite(cv::norm(tvec)) || tvec[2] <= 0) {
      s.skipped.push_back({v.name, "PnP failed"});
      continue;
    }
    BoardPoseEstimate e;
    e.name = v.name;
    e.camera_from_board = PoseOf(rvec, tvec);
    e.points = static_cast<int>(v.image_points.size());
    std::vector<cv::Point2f> projected;
    const Eigen::MatrixXd j =
        PoseColumns(ProjectionJacobian(camera, v.object_points, e.camera_from_board, &projected), e.camera_from_board.linear());
    const double view_ss = SquaredResidual(v.image_points, projected);
    e.rms_px = std::sqrt(view_ss / e.points);
    ss += view_ss;
    n += e.points;
    information.push_back(j.transpose() * j);
    out.push_back(e);
  }
  s.used = static_cast<int>(out.size());
  const long long dof = 2 * n - 6LL * s.used;
  s.rms_px = n > 0 ? std::sqrt(ss / n) : 0.0;
  s.sigma_estimated = options.sigma_px <= 0;
  s.sigma_px = s.sigma_estimated ? (dof > 0 ? std::sqrt(ss / dof) : 0.0) : options.sigma_px;
  for (std::size_t i = 0; i < out.size(); ++i) out[i].covariance = s.sigma_px * s.sigma_px * InverseOrZero(information[i]);
  if (summary) *summary = s;
  return out;
}

std::vector<BoardPoseEstimate> BoardPosesFromCalibration(const CameraCalibrationResult& calibration,
                                                         const std::vector<ViewPoints>& views,
                                                         const CameraCalibrationOptions& options) {
  std::map<std::string, const ViewPoints*> by_name;
  for (const ViewPoints& v : views) by_name[v.name] = &v;
  // Intrinsic columns of OpenCV's Jacobian (fx fy cx cy k1 k2 p1 p2 k3 at 6..14) that were
  // estimated; a fixed aspect ratio ties fy to fx (one column fx + (fy/fx)·fy).
  const camera::CameraIntrinsics& cam = calibration.intrinsics;
  const int nv = static_cast<int>(calibration.view_names.size());
  std::vector<Eigen::MatrixXd> je(nv), ji(nv);
  std::vector<BoardPoseEstimate> out(nv);
  double ss = 0;
  long long n = 0;
  for (int v = 0; v < nv; ++v) {
    const auto it = by_name.find(calibration.view_names[v]);
    if (it == by_name.end())
      throw InputError({"", 0, "views"}, "no detection for the calibrated view " + calibration.view_names[v]);
    const ViewPoints& view = *it->second;
    BoardPoseEstimate& e = out[v];
    e.name = view.name;
    e.camera_from_board = PoseOf(calibration.rvecs[v], calibration.tvecs[v]);
    e.points = static_cast<int>(view.image_points.size());
    std::vector<cv::Point2f> projected;
    const Eigen::MatrixXd j = ProjectionJacobian(cam, view.object_points, e.camera_from_board, &projected);
    const double view_ss = SquaredResidual(view.image_points, projected);
    e.rms_px = std::sqrt(view_ss / std::max(1, e.points));
    ss += view_ss;
    n += e.points;
    je[v] = PoseColumns(j, e.camera_from_board.linear());
    std::vector<Eigen::VectorXd> cols;
    cols.push_back(options.fix_aspect_ratio ? Eigen::VectorXd(j.col(6) + (cam.fy / cam.fx) * j.col(7))
                                            : Eigen::VectorXd(j.col(6)));
    if (!options.fix_aspect_ratio) cols.push_back(j.col(7));
    cols.push_back(j.col(8));
    cols.push_back(j.col(9));
    cols.push_back(j.col(10));  // k1
    cols.push_back(j.col(11));  // k2
    if (!options.zero_tangential) cols.push_back(j.col(12)), cols.push_back(j.col(13));
    if (!options.fix_k3) cols.push_back(j.col(14));
    ji[v].resize(j.rows(), static_cast<int>(cols.size()));
    for (std::size_t c = 0; c < cols.size(); ++c) ji[v].col(static_cast<int>(c)) = cols[c];
  }
  if (nv == 0) return out;
  const int p = static_cast<int>(ji[0].cols());
  // Information matrix in arrow form: A (intrinsics), B_v (view poses), C_v (cross); the pose
  // block of the inverse is B⁻¹ + B⁻¹ Cᵀ S⁻¹ C B⁻¹ with S = A − Σ C B⁻¹ Cᵀ (Schur complement).
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p, p), schur;
  std::vector<Mat6> b_inv(nv);
  std::vector<Eigen::MatrixXd> c(nv);
  for (int v = 0; v < nv; ++v) {
    a += ji[v].transpose() * ji[v];
    b_inv[v] = InverseOrZero(je[v].transpose() * je[v]);
    c[v] = ji[v].transpose() * je[v];
  }
  schur = a;
  for (int v = 0; v < nv; ++v) schur -= c[v] * b_inv[v] * c[v].transpose();
  const Eigen::MatrixXd schur_inv = schur.fullPivLu().inverse();
  const long long dof = 2 * n - (p + 6LL * nv);
  const double sigma2 = dof > 0 ? ss / dof : 0.0;
  for (int v = 0; v < nv; ++v) {
    const Eigen::MatrixXd cb = c[v] * b_inv[v];
    out[v].covariance = sigma2 * (b_inv[v] + cb.transpose() * schur_inv * cb);
  }
  return out;
}

std::string FormatBoardPoseEstimates(const std::vector<BoardPoseEstimate>& poses, const std::string& comment) {
  std::vector<std::string> header = {"pose", "image", "x", "y", "z", "a", "b", "c", "points", "rms_px"};
  for (int i = 0; i < 6; ++i)
    for (int k = i; k < 6; ++k) header.push_back("cov_" + std::to_string(i) + std::to_string(k));
  // [ω (rad); t] → [ω (deg); t]
  Mat6 to_deg = Mat6::Identity();
  to_deg.topLeftCorner<3, 3>() *= RadToDeg(1.0);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    const BoardPoseEstimate& e = poses[p];
    std::vector<std::string> row = {std::to_string(e.pose > 0 ? e.pose : static_cast<int>(p) + 1), e.name};
    for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(e.camera_from_board.translation()[k], 6));
    const KukaAbc abc = KukaAbcFromRotation(e.camera_from_board.linear());
    for (double v : {abc.a, abc.b, abc.c}) row.push_back(FormatFixed(RadToDeg(v), 9));
    row.push_back(std::to_string(e.points));
    row.push_back(FormatFixed(e.rms_px, 5));
    const Mat6 cov = to_deg * e.covariance * to_deg;
    for (int i = 0; i < 6; ++i)
      for (int k = i; k < 6; ++k) row.push_back(FormatSignificant(cov(i, k), 10));
    rows.push_back(row);
  }
  return FormatCsv(header, rows, comment);
}

}  // namespace ramtk::calib
