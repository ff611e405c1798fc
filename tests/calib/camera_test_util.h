#pragma once
// Rendered calibration sessions with known truth for the camera calibration tests.
#include <cmath>
#include <cstdint>
#include <opencv2/calib3d.hpp>
#include <random>
#include <string>
#include <vector>

#include "ramtk/calib/board_renderer.h"
#include "ramtk/calib/camera_calibration.h"
#include "ramtk/camera/opencv_camera.h"

namespace ramtk::calib::testing {

// A 640×480 camera with moderate barrel distortion (truth for the tests).
inline camera::CameraIntrinsics TruthCamera(bool right = false) {
  const cv::Matx33d k =
      right ? cv::Matx33d(760, 0, 315, 0, 758, 246, 0, 0, 1) : cv::Matx33d(750, 0, 328, 0, 752, 236, 0, 0, 1);
  const std::vector<double> d = right ? std::vector<double>{-0.15, 0.10, -0.0004, 0.0006, 0.0}
                                      : std::vector<double>{-0.12, 0.08, 0.0005, -0.0003, 0.0};
  return camera::IntrinsicsFromOpenCv(k, d, cv::Size(640, 480));
}

// fx fy cx cy k1 k2 p1 p2 of a camera: the order of OpenCV's stdDeviationsIntrinsics.
inline std::vector<double> IntrinsicValues(const camera::CameraIntrinsics& c) {
  return {c.fx, c.fy, c.cx, c.cy, c.distortion.k1, c.distortion.k2, c.distortion.p1, c.distortion.p2};
}

// R and T of a calibrated rig in OpenCV's types, and their σ (rotation vector rad, T mm) from
// parameter_std (kCalibParameterStdOrder: entries 18..23).
inline cv::Matx33d RigRotation(const StereoCalibrationResult& st) {
  cv::Matx33d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = st.rig.right_from_left.linear()(i, j);
  return r;
}
inline cv::Vec3d RigTranslation(const StereoCalibrationResult& st) {
  const Vec3 t = st.rig.right_from_left.translation();
  return {t.x(), t.y(), t.z()};
}
inline cv::Vec6d RigStdRt(const StereoCalibrationResult& st) {
  cv::Vec6d s = cv::Vec6d::all(0.0);
  if (st.rig.parameter_std.size() == 24)
    for (int k = 0; k < 6; ++k) s[k] = st.rig.parameter_std[18 + k];
  return s;
}

// right_from_left of the truth stereo rig: 120 mm baseline, 4° toe-in.
inline void TruthStereo(cv::Matx33d* r, cv::Vec3d* t) {
  cv::Rodrigues(cv::Vec3d(0.0, -4.0 * CV_PI / 180.0, 0.3 * CV_PI / 180.0), *r);
  *t = cv::Vec3d(-120.0, 0.8, 3.0);
}

// Extent of the board's features (mm) for visibility checks.
inline std::vector<cv::Point3f> BoardOutline(const BoardSpec& b) {
  const std::vector<cv::Point3f> p = BoardObjectPoints(b);
  float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
  for (const cv::Point3f& q : p)
    x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
  const float m = static_cast<float>(b.square_mm);
  return {{x0 - m, y0 - m, 0}, {x1 + m, y0 - m, 0}, {x1 + m, y1 + m, 0}, {x0 - m, y1 + m, 0}};
}

inline bool Visible(const std::vector<cv::Point3f>& outline, const cv::Vec3d& r, const cv::Vec3d& t,
                    const camera::CameraIntrinsics& cam) {
  const std::vector<cv::Point2d> p =
      camera::ProjectPointsOpenCv({outline.begin(), outline.end()}, r, t, cam);  // any lens model
  for (const cv::Point2d& q : p) {
    if (q.x < 8 || q.y < 8 || q.x > cam.width - 9 || q.y > cam.height - 9) return false;
  }
  return true;
}

// camera_from_board poses spread over the image: distance 380–560 mm, tilts up to 40°. If
// `right` is given, poses must also be visible in it (x_right = R·x_left + T).
inline void RandomBoardPoses(const BoardSpec& board, const camera::CameraIntrinsics& cam, int count, unsigned seed,
                             std::vector<cv::Vec3d>* rvecs, std::vector<cv::Vec3d>* tvecs,
                             const camera::CameraIntrinsics* right = nullptr, const cv::Matx33d* r_rl = nullptr,
                             const cv::Vec3d* t_rl = nullptr) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::vector<cv::Point3f> outline = BoardOutline(board);
  cv::Point3f centre(0, 0, 0);
  for (const cv::Point3f& q : outline) centre += 0.25f * q;
  while (static_cast<int>(rvecs->size()) < count) {
    cv::Vec3d axis(u(rng), u(rng), 0.3 * u(rng));
    const double tilt = (10.0 + 30.0 * std::abs(u(rng))) * CV_PI / 180.0;
    cv::Vec3d rv = axis * (tilt / cv::norm(axis));
    cv::Matx33d r;
    cv::Rodrigues(rv, r);
    const double z = 380.0 + 180.0 * (0.5 + 0.5 * u(rng));
    const cv::Vec3d target(0.35 * z * u(rng), 0.25 * z * u(rng), z);
    const cv::Vec3d t = target - r * cv::Vec3d(centre.x, centre.y, 0.0);
    if (!Visible(outline, rv, t, cam)) continue;
    if (right) {
      cv::Vec3d rv2;
      cv::Rodrigues(*r_rl * r, rv2);
      if (!Visible(outline, rv2, *r_rl * t + *t_rl, *right)) continue;
    }
    rvecs->push_back(rv);
    tvecs->push_back(t);
  }
}

// One rendered stereo session: `count` board poses visible in both cameras of the truth rig,
// rendered by `left` / `right` (cameras TruthCamera(false/true)), image noise seeded from
// noise_base (left 2v, right 2v + 1 added).
struct StereoImages {
  std::vector<cv::Mat> left, right;
};

inline StereoImages RenderStereoImages(const BoardSpec& board, const BoardRenderer& left, const BoardRenderer& right,
                                       int count, unsigned pose_seed, std::uint64_t noise_base) {
  const camera::CameraIntrinsics cl = TruthCamera(false), cr = TruthCamera(true);
  cv::Matx33d r_rl;
  cv::Vec3d t_rl;
  TruthStereo(&r_rl, &t_rl);
  std::vector<cv::Vec3d> rvecs, tvecs;
  RandomBoardPoses(board, cl, count, pose_seed, &rvecs, &tvecs, &cr, &r_rl, &t_rl);
  StereoImages s;
  for (int v = 0; v < count; ++v) {
    cv::Matx33d r;
    cv::Rodrigues(rvecs[v], r);
    cv::Vec3d rv_right;
    cv::Rodrigues(r_rl * r, rv_right);
    s.left.push_back(left.Render(rvecs[v], tvecs[v], noise_base + 2 * v));
    s.right.push_back(right.Render(rv_right, r_rl * tvecs[v] + t_rl, noise_base + 2 * v + 1));
  }
  return s;
}

// Board detections of rendered images as calibration views named prefix + index (empty points
// where the board was not found).
inline std::vector<ViewPoints> DetectViews(const std::vector<cv::Mat>& images, const BoardSpec& board,
                                           const BoardDetectOptions& options, const std::string& prefix) {
  std::vector<ViewPoints> views;
  for (std::size_t v = 0; v < images.size(); ++v) {
    const BoardDetection d = DetectBoard(images[v], board, options);
    ViewPoints p;
    p.name = prefix + std::to_string(v);
    if (d.found) p.image_points = d.image_points, p.object_points = d.object_points, p.ids = d.ids;
    views.push_back(p);
  }
  return views;
}

// Errors of a stereo calibration against the truth rig, in the order of StereoParameterName:
// per camera (left, then right) fx fy cx cy k1 k2 p1 p2, then R (rotation vector of
// R_est·R_trueᵀ, rad) and T (mm); with the σ the calibration reported for each.
constexpr int kStereoParameters = 22;
inline const char* StereoParameterName(int i) {
  static const char* names[kStereoParameters] = {"L.fx", "L.fy", "L.cx", "L.cy", "L.k1", "L.k2", "L.p1", "L.p2",
                                                 "R.fx", "R.fy", "R.cx", "R.cy", "R.k1", "R.k2", "R.p1", "R.p2",
                                                 "rx",   "ry",   "rz",   "Tx",   "Ty",   "Tz"};
  return names[i];
}

inline void StereoErrors(const StereoCalibrationResult& st, std::vector<double>* error, std::vector<double>* sigma) {
  error->assign(kStereoParameters, 0.0);
  sigma->assign(kStereoParameters, 0.0);
  // The rig's jointly refined intrinsics with their σ from parameter_std (9 per camera).
  for (int c = 0; c < 2; ++c) {
    const std::vector<double> tru = IntrinsicValues(TruthCamera(c == 1));
    const std::vector<double> est = IntrinsicValues(c == 0 ? st.rig.left : st.rig.right);
    for (int i = 0; i < 8; ++i) {
      (*error)[8 * c + i] = est[i] - tru[i];
      (*sigma)[8 * c + i] = st.rig.parameter_std.size() == 24 ? st.rig.parameter_std[9 * c + i] : 0.0;
    }
  }
  cv::Matx33d r_true;
  cv::Vec3d t_true;
  TruthStereo(&r_true, &t_true);
  cv::Vec3d dr;
  cv::Rodrigues(RigRotation(st) * r_true.t(), dr);
  const cv::Vec3d t = RigTranslation(st);
  const cv::Vec6d std_rt = RigStdRt(st);
  for (int k = 0; k < 3; ++k) {
    (*error)[16 + k] = dr[k];
    (*error)[19 + k] = t[k] - t_true[k];
    (*sigma)[16 + k] = std_rt[k];
    (*sigma)[19 + k] = std_rt[3 + k];
  }
}

}  // namespace ramtk::calib::testing
