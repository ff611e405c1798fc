#pragma once
// Renders calibration boards seen by a pinhole camera with lens distortion (camera::CameraIntrinsics), for tests with
// known truth. Each output pixel is the mean of supersample² sub-pixel rays (one per cell of an s×s grid, jittered
// within its cell by default); a ray is the exact undistorted direction of its sub-pixel position (OpenCV's model, k1
// k2 p1 p2 k3), intersected with the board plane. Chessboards and circle grids are evaluated analytically; ChArUco
// boards are sampled bilinearly from OpenCV's board drawing. Gaussian noise is added with a fixed seed.

#include <cstdint>
#include <opencv2/core.hpp>

#include "ramtk/calib/board.h"
#include "ramtk/camera/camera_model.h"

namespace ramtk::calib {

struct BoardRenderOptions {
  int supersample = 3;  // sub-pixel rays per axis
  // Each sub-pixel ray at a fixed pseudo-random place in its cell (stratified jitter) instead of
  // the cell centre. A regular s×s grid quantises where an edge crosses a pixel, which leaves a
  // corner error fixed by the geometry; jitter turns it into an error that varies from pixel to
  // pixel and averages out over a corner's window.
  bool jitter = true;
  double black = 40.0;             // grey level of dark board areas
  double white = 215.0;            // grey level of bright board areas
  double background = 100.0;       // grey level off the board
  double blur_sigma_px = 0.0;      // Gaussian blur of the optics (px, 1σ) before the noise; 0 = none
  double noise_sigma = 1.0;        // Gaussian noise (grey levels, 1σ) added before rounding to 8 bit
  double margin_squares = 1.0;     // white border around the pattern, in squares / spacings
  double texture_px_per_mm = 8.0;  // ChArUco texture resolution

  std::string Validate() const;
};

class BoardRenderer {
 public:
  // Precomputes the ray of every sub-pixel (a few hundred ms for VGA at supersample 3).
  BoardRenderer(const BoardSpec& board, const camera::CameraIntrinsics& camera, const BoardRenderOptions& options);
  // 8-bit grey image of the board at camera_from_board = (rvec, tvec) (Rodrigues, mm). Pixels
  // whose rays miss the board or meet it from behind show the background.
  cv::Mat Render(const cv::Vec3d& rvec, const cv::Vec3d& tvec, std::uint64_t noise_seed) const;
  // Largest reprojection error (px) of the precomputed rays: a self-check of the undistortion.
  double RayMapError() const { return ray_map_error_px_; }

 private:
  double BoardValue(double x_mm, double y_mm) const;  // 0 = black .. 1 = white; -1 off the board

  BoardSpec board_;
  camera::CameraIntrinsics camera_;
  BoardRenderOptions options_;
  cv::Mat rays_;                    // CV_64FC2, (height·s) × (width·s): normalized undistorted x, y
  cv::Mat texture_;                 // ChArUco only: CV_32F in [0, 1]
  cv::Matx23d texture_from_board_;  // ChArUco only
  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;  // board extent incl. margin (mm)
  double ray_map_error_px_ = 0.0;
};

}  // namespace ramtk::calib
