#include "ramtk/calib/board_renderer.h"

#include <cmath>
#include <cstdint>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "board_internal.h"
#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/cell_jitter.h"
#include "ramtk/core/error.h"

namespace ramtk::calib {
namespace {

// Sub-pixel sample offset in [0, 1) along one axis of cell (x, y): the cell centre, or with
// jitter a fixed hash of the cell (the same in every render and in the self-check).
double SampleOffset(int x, int y, int axis, bool jitter) { return jitter ? CellJitter(x, y, axis) : 0.5; }

}  // namespace

std::string BoardRenderOptions::Validate() const {
  if (supersample < 1 || supersample > 8) return "supersample must be in 1..8";
  if (!(noise_sigma >= 0.0)) return "noise_sigma must be >= 0";
  if (!(blur_sigma_px >= 0.0)) return "blur_sigma_px must be >= 0";
  if (!(margin_squares >= 0.0)) return "margin_squares must be >= 0";
  if (!(texture_px_per_mm > 0.0)) return "texture_px_per_mm must be positive";
  return "";
}

BoardRenderer::BoardRenderer(const BoardSpec& board, const camera::CameraIntrinsics& camera,
                             const BoardRenderOptions& options)
    : board_(board), camera_(camera), options_(options) {
  ThrowIfInvalid(board.Validate(), "board");
  ThrowIfInvalid(options.Validate(), "BoardRenderOptions");
  const int s = options.supersample;
  if (camera.width < 1 || camera.height < 1) throw InputError({"", 0, "camera"}, "image size must be positive");
  const int w = camera.width * s, h = camera.height * s;
  // Undistort every sub-pixel by Gauss-Newton on the camera's lens model (camera::UndistortNormalized;
  // cv::undistortPoints' fixed-point iteration is far slower at this accuracy).
  rays_.create(h, w, CV_64FC2);
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& range) {
    for (int y = range.start; y < range.end; ++y) {
      cv::Vec2d* row = rays_.ptr<cv::Vec2d>(y);
      for (int x = 0; x < w; ++x) {
        const double u = (x + SampleOffset(x, y, 0, options.jitter)) / s - 0.5;
        const double v = (y + SampleOffset(x, y, 1, options.jitter)) / s - 0.5;
        const camera::Vec2 ideal =
            camera::UndistortNormalized(camera.distortion, {(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy});
        row[x] = cv::Vec2d(ideal.x(), ideal.y());
      }
    }
  });
  // Self-check on a sparse subset: project the rays back with OpenCV.
  std::vector<cv::Point3d> check;
  std::vector<cv::Point2d> expected;
  for (int y = 0; y < h; y += 37) {
    for (int x = 0; x < w; x += 41) {
      const cv::Vec2d& r = rays_.at<cv::Vec2d>(y, x);
      check.emplace_back(r[0], r[1], 1.0);
      expected.emplace_back((x + SampleOffset(x, y, 0, options.jitter)) / s - 0.5,
                            (y + SampleOffset(x, y, 1, options.jitter)) / s - 0.5);
    }
  }
  const std::vector<cv::Point2d> back =
      camera::ProjectPointsOpenCv(check, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera);
  for (std::size_t i = 0; i < back.size(); ++i) {
    ray_map_error_px_ = std::max(ray_map_error_px_, cv::norm(back[i] - expected[i]));
  }

  const double m = options.margin_squares * board.square_mm;
  const double sq = board.square_mm;
  switch (board.type) {
    case BoardType::kChessboard:  // squares around the inner corners: X in [-sq, cols·sq]
      min_x_ = -sq - m, min_y_ = -sq - m, max_x_ = board.cols * sq + m, max_y_ = board.rows * sq + m;
      break;
    case BoardType::kSymmetricCircles:
      min_x_ = -m, min_y_ = -m, max_x_ = (board.cols - 1) * sq + m, max_y_ = (board.rows - 1) * sq + m;
      break;
    case BoardType::kAsymmetricCircles:
      min_x_ = -m, min_y_ = -m, max_x_ = (2 * board.cols - 1) * sq + m, max_y_ = (board.rows - 1) * sq + m;
      break;
    case BoardType::kCharuco: {
      const double ppmm = options.texture_px_per_mm;
      const cv::Size size(static_cast<int>(std::lround(board.cols * sq * ppmm)),
                          static_cast<int>(std::lround(board.rows * sq * ppmm)));
      cv::Mat drawing;
      const cv::Ptr<cv::aruco::CharucoBoard> cb = internal::MakeCharucoBoard(board);
      cb->draw(size, drawing, 0, 1);
      drawing.convertTo(texture_, CV_32F, 1.0 / 255.0);
      // Where OpenCV draws the corners: fit texture_from_board to the corners found in the drawing
      // (the drawing's y axis may run opposite to the object points').
      const BoardDetection det = DetectBoard(drawing, board, 4);
      if (!det.found) throw std::runtime_error("ChArUco texture: corners not found in OpenCV's drawing");
      cv::Mat a(static_cast<int>(2 * det.ids.size()), 6, CV_64F, cv::Scalar(0)), b(a.rows, 1, CV_64F);
      for (int i = 0; i < static_cast<int>(det.ids.size()); ++i) {
        const cv::Point3f& p = det.object_points[i];
        a.at<double>(2 * i, 0) = p.x, a.at<double>(2 * i, 1) = p.y, a.at<double>(2 * i, 2) = 1.0;
        a.at<double>(2 * i + 1, 3) = p.x, a.at<double>(2 * i + 1, 4) = p.y, a.at<double>(2 * i + 1, 5) = 1.0;
        b.at<double>(2 * i) = det.image_points[i].x;
        b.at<double>(2 * i + 1) = det.image_points[i].y;
      }
      cv::Mat x;
      cv::solve(a, b, x, cv::DECOMP_SVD);
      for (int i = 0; i < 6; ++i) texture_from_board_(i / 3, i % 3) = x.at<double>(i);
      min_x_ = -m, min_y_ = -m, max_x_ = board.cols * sq + m, max_y_ = board.rows * sq + m;
      break;
    }
  }
}

double BoardRenderer::BoardValue(double x, double y) const {
  if (x < min_x_ || x > max_x_ || y < min_y_ || y > max_y_) return -1.0;
  const double sq = board_.square_mm;
  switch (board_.type) {
    case BoardType::kChessboard: {
      if (x < -sq || y < -sq || x >= board_.cols * sq || y >= board_.rows * sq) return 1.0;  // margin
      const long i = static_cast<long>(std::floor(x / sq)), j = static_cast<long>(std::floor(y / sq));
      return ((i + j) & 1) == 0 ? 0.0 : 1.0;
    }
    case BoardType::kSymmetricCircles:
    case BoardType::kAsymmetricCircles: {
      const double r = 0.5 * board_.CircleDiameterMm();
      const long row = std::lround(y / sq);
      for (long i = row - 1; i <= row + 1; ++i) {
        if (i < 0 || i >= board_.rows) continue;
        const double shift = board_.type == BoardType::kAsymmetricCircles ? (i % 2) * sq : 0.0;
        const double step = board_.type == BoardType::kAsymmetricCircles ? 2.0 * sq : sq;
        const long j = std::lround((x - shift) / step);
        for (long jj = j - 1; jj <= j + 1; ++jj) {
          if (jj < 0 || jj >= board_.cols) continue;
          const double dx = x - (shift + jj * step), dy = y - i * sq;
          if (dx * dx + dy * dy <= r * r) return 0.0;
        }
      }
      return 1.0;
    }
    case BoardType::kCharuco: {
      const double u = texture_from_board_(0, 0) * x + texture_from_board_(0, 1) * y + texture_from_board_(0, 2);
      const double v = texture_from_board_(1, 0) * x + texture_from_board_(1, 1) * y + texture_from_board_(1, 2);
      // Bilinear; texel centres at integers (OpenCV's pixel convention, as the corner fit used).
      const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
      if (u0 < 0 || v0 < 0 || u0 + 1 >= texture_.cols || v0 + 1 >= texture_.rows) return 1.0;  // white margin
      const double fu = u - u0, fv = v - v0;
      const float* r0 = texture_.ptr<float>(v0);
      const float* r1 = texture_.ptr<float>(v0 + 1);
      return (1 - fv) * ((1 - fu) * r0[u0] + fu * r0[u0 + 1]) + fv * ((1 - fu) * r1[u0] + fu * r1[u0 + 1]);
    }
  }
  return -1.0;
}

cv::Mat BoardRenderer::Render(const cv::Vec3d& rvec, const cv::Vec3d& tvec, std::uint64_t noise_seed) const {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  // Ray d = (x, y, 1) meets the plane z_board = 0: board point (X, Y) with
  //   λ·d = R·(X, Y, 0) + t  →  d ∝ H·(X, Y, 1), H = [r1 r2 t].
  const cv::Matx33d h(r(0, 0), r(0, 1), tvec[0], r(1, 0), r(1, 1), tvec[1], r(2, 0), r(2, 1), tvec[2]);
  const cv::Matx33d hinv = h.inv();
  const int s = options_.supersample;
  cv::Mat ideal(camera::ImageSize(camera_), CV_64F);
  std::mt19937_64 rng(noise_seed * 0x9E3779B97F4A7C15ULL + 12345);
  std::normal_distribution<double> gauss(0.0, 1.0);
  cv::parallel_for_(cv::Range(0, camera_.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      for (int x = 0; x < camera_.width; ++x) {
        double sum = 0.0;
        for (int sy = 0; sy < s; ++sy) {
          const cv::Vec2d* row = rays_.ptr<cv::Vec2d>(y * s + sy);
          for (int sx = 0; sx < s; ++sx) {
            const cv::Vec2d& d = row[x * s + sx];
            const cv::Vec3d b = hinv * cv::Vec3d(d[0], d[1], 1.0);
            double value = -1.0;
            // In front of the camera: the point λ·d with λ = 1 / b[2] must have λ > 0.
            if (b[2] > 0.0) value = BoardValue(b[0] / b[2], b[1] / b[2]);
            sum += value < 0.0 ? options_.background : options_.black + value * (options_.white - options_.black);
          }
        }
        ideal.at<double>(y, x) = sum / (s * s);
      }
    }
  });
  // Noise drawn in a fixed order after the parallel part, so images do not depend on threads.
  if (options_.blur_sigma_px > 0.0) cv::GaussianBlur(ideal, ideal, cv::Size(0, 0), options_.blur_sigma_px);
  cv::Mat out(camera::ImageSize(camera_), CV_8U);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      out.at<unsigned char>(y, x) =
          cv::saturate_cast<unsigned char>(ideal.at<double>(y, x) + options_.noise_sigma * gauss(rng));
    }
  }
  return out;
}

}  // namespace ramtk::calib
