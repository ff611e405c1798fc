#pragma once
// Calibration boards: chessboard, symmetric / asymmetric circle grid, ChArUco. Object points
// follow OpenCV's conventions (z = 0 plane, mm), so detections feed cv::calibrateCamera directly.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/core/error.h"

namespace ramtk::calib {

enum class BoardType { kChessboard, kSymmetricCircles, kAsymmetricCircles, kCharuco };

struct BoardSpec {
  BoardType type = BoardType::kChessboard;
  // Chessboard: inner corners per row (cols) and per column (rows). Circle grids: circles per
  // row and per column as OpenCV's patternSize (asymmetric: rows are offset by half a step).
  // ChArUco: squares per row and per column.
  int cols = 9;
  int rows = 6;
  // Square side (chessboard, ChArUco) or circle spacing (mm). For the asymmetric grid this is
  // OpenCV's unit: centres at ((2j + i mod 2)·s, i·s).
  double square_mm = 25.0;
  double marker_mm = 18.0;          // ChArUco marker side (mm)
  double circle_diameter_mm = 0.0;  // circle grids; 0 → 0.5·square_mm (symmetric), 0.7·square_mm (asymmetric)
  std::string dictionary = "DICT_5X5_100";  // ChArUco dictionary (cv::aruco predefined name)

  std::string Validate() const;  // empty if valid
  double CircleDiameterMm() const;
  std::string ToString() const;  // the text ParseBoardSpec reads
};

// "chessboard:9x6:25", "circles:4x11:20[:diameter]", "acircles:4x11:20[:diameter]",
// "charuco:10x7:25:18[:DICT_5X5_100]" (COLSxROWS, then mm). InputError at `where`.
BoardSpec ParseBoardSpec(const std::string& text, const InputLocation& where);
// A board given on a command line: the description itself, or a file holding it (its first line
// that is neither blank nor a '#' comment). Errors name the file and line, or `option`.
BoardSpec ReadBoardSpecArgument(const std::string& text_or_path, const std::string& option = "--board");
// The board images of one camera: the PNG, BMP, JPEG and TIFF files of `folder`, sorted by name.
// InputError if it is not a folder or holds none.
std::vector<std::string> ListBoardImages(const std::string& folder);

// Every feature of the board in board coordinates (mm, z = 0), in OpenCV's order. For ChArUco,
// index i is the chessboard corner with id i.
std::vector<cv::Point3f> BoardObjectPoints(const BoardSpec& board);

struct BoardDetection {
  bool found = false;
  std::vector<cv::Point2f> image_points;   // pixels (OpenCV: integer coordinates at pixel centres)
  std::vector<cv::Point3f> object_points;  // matching board points (mm)
  std::vector<int> ids;                    // feature index into BoardObjectPoints
  std::string reason;                      // why not found
  // Chessboards refined with kSubPix whose grid came from the sector-based detector: that
  // detector's own (kSectorBased) positions, so that one detection gives both corner sets;
  // otherwise empty.
  std::vector<cv::Point2f> sector_points;
};

// How chessboard corners are refined after detection.
enum class CornerRefinement {
  // findChessboardCornersSB's own (CALIB_CB_ACCURACY) positions. Their error is small (≈0.03 px)
  // but fixed by the geometry and correlated across the board: on rendered stereo sessions it
  // biased fx by +1.1–1.5 px (7–10 reported σ) and T_z by +0.2 mm (docs/calib.md).
  kSectorBased,
  // The detected corners refined by cv::cornerSubPix, each with its own half-window
  // (subpix_window_fraction × the distance to its nearest grid neighbour, px), so the window
  // follows the imaged square size and never reaches the next corner. Errors then behave like
  // independent noise and the reported σ hold (docs/calib.md).
  kSubPix,
};

struct BoardDetectOptions {
  CornerRefinement refinement = CornerRefinement::kSubPix;  // chessboards only
  double subpix_window_fraction = 0.35;                     // kSubPix half-window / nearest-neighbour corner distance
  int subpix_min_half_window = 2;                           // px; lower bound of that half-window
  int min_charuco_corners = 6;                              // a ChArUco detection needs at least this many corners

  std::string Validate() const;  // empty if valid
};

// Detects the board in an 8-bit grey image (sub-pixel refined for chessboards, see
// CornerRefinement). InputError if the options are invalid.
BoardDetection DetectBoard(const cv::Mat& gray, const BoardSpec& board, const BoardDetectOptions& options);
// The default options with another ChArUco minimum.
BoardDetection DetectBoard(const cv::Mat& gray, const BoardSpec& board, int min_charuco_corners = 6);

}  // namespace ramtk::calib
