#pragma once
// Rendered calibration sessions with known truth for the camera calibration tests.
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <random>
#include <vector>

#include "ramtk/calib/board_renderer.h"
#include "ramtk/calib/camera_calibration.h"

namespace ramtk::calib::testing {

// A 640×480 camera with moderate barrel distortion (truth for the tests).
inline PinholeCamera TruthCamera(bool right = false) {
  PinholeCamera c;
  c.image_size = cv::Size(640, 480);
  c.camera_matrix =
      right ? cv::Matx33d(760, 0, 315, 0, 758, 246, 0, 0, 1) : cv::Matx33d(750, 0, 328, 0, 752, 236, 0, 0, 1);
  c.distortion = right ? cv::Vec<double, 5>(-0.15, 0.10, -0.0004, 0.0006, 0.0)
                       : cv::Vec<double, 5>(-0.12, 0.08, 0.0005, -0.0003, 0.0);
  return c;
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
                    const PinholeCamera& cam) {
  std::vector<cv::Point2f> p;
  cv::projectPoints(outline, r, t, cam.camera_matrix, cam.distortion, p);
  for (const cv::Point2f& q : p) {
    if (q.x < 8 || q.y < 8 || q.x > cam.image_size.width - 9 || q.y > cam.image_size.height - 9) return false;
  }
  return true;
}

// camera_from_board poses spread over the image: distance 380–560 mm, tilts up to 40°. If
// `right` is given, poses must also be visible in it (x_right = R·x_left + T).
inline void RandomBoardPoses(const BoardSpec& board, const PinholeCamera& cam, int count, unsigned seed,
                             std::vector<cv::Vec3d>* rvecs, std::vector<cv::Vec3d>* tvecs,
                             const PinholeCamera* right = nullptr, const cv::Matx33d* r_rl = nullptr,
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

}  // namespace ramtk::calib::testing
