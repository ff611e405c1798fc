#include "ramtk/calib/board.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "board_internal.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/parse.h"

namespace ramtk::calib {
namespace {

const std::map<std::string, int>& Dictionaries() {
  static const std::map<std::string, int> d = {{"DICT_4X4_50", cv::aruco::DICT_4X4_50},
                                               {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
                                               {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
                                               {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
                                               {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
                                               {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
                                               {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
                                               {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
                                               {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
                                               {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
                                               {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
                                               {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11}};
  return d;
}

// cornerSubPix on each corner of a cols × rows grid with a half-window scaled to the distance
// to its nearest grid neighbour: the gradient window then covers the same share of a square
// however near or oblique the board, and never reaches into the neighbouring corner.
void RefineCornersAdaptive(const cv::Mat& gray, int cols, int rows, const BoardDetectOptions& o,
                           std::vector<cv::Point2f>* pts) {
  const std::vector<cv::Point2f> start = *pts;
  const cv::TermCriteria criteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const int k = i * cols + j;
      double nearest = 1e30;
      for (const cv::Point2i& n :
           {cv::Point2i(j - 1, i), cv::Point2i(j + 1, i), cv::Point2i(j, i - 1), cv::Point2i(j, i + 1)}) {
        if (n.x < 0 || n.y < 0 || n.x >= cols || n.y >= rows) continue;
        nearest = std::min(nearest, static_cast<double>(cv::norm(start[n.y * cols + n.x] - start[k])));
      }
      const int half =
          std::max(o.subpix_min_half_window, static_cast<int>(std::lround(o.subpix_window_fraction * nearest)));
      std::vector<cv::Point2f> one = {start[k]};
      cv::cornerSubPix(gray, one, cv::Size(half, half), cv::Size(-1, -1), criteria);
      (*pts)[k] = one[0];
    }
  }
}

}  // namespace

namespace internal {

cv::Ptr<cv::aruco::CharucoBoard> MakeCharucoBoard(const BoardSpec& board) {
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(
      static_cast<cv::aruco::PREDEFINED_DICTIONARY_NAME>(Dictionaries().at(board.dictionary)));
  return cv::aruco::CharucoBoard::create(board.cols, board.rows, static_cast<float>(board.square_mm),
                                         static_cast<float>(board.marker_mm), dict);
}

}  // namespace internal

std::string BoardSpec::Validate() const {
  const int min_cols = type == BoardType::kCharuco ? 3 : 2;
  if (cols < min_cols || rows < min_cols || cols > 200 || rows > 200) return "board size out of range";
  if (!(square_mm > 0.0)) return "square/spacing must be positive";
  if (type == BoardType::kCharuco) {
    if (!(marker_mm > 0.0 && marker_mm < square_mm)) return "ChArUco marker must be smaller than the square";
    if (Dictionaries().count(dictionary) == 0) return "unknown ArUco dictionary '" + dictionary + "'";
  }
  if (type == BoardType::kSymmetricCircles || type == BoardType::kAsymmetricCircles) {
    const double limit = type == BoardType::kSymmetricCircles ? square_mm : square_mm * 1.41;
    if (circle_diameter_mm < 0.0 || CircleDiameterMm() >= limit) return "circles would touch";
  }
  return "";
}

double BoardSpec::CircleDiameterMm() const {
  if (circle_diameter_mm > 0.0) return circle_diameter_mm;
  return type == BoardType::kAsymmetricCircles ? 0.7 * square_mm : 0.5 * square_mm;
}

std::string BoardSpec::ToString() const {
  char buf[200];
  switch (type) {
    case BoardType::kChessboard:
      std::snprintf(buf, sizeof(buf), "chessboard:%dx%d:%g", cols, rows, square_mm);
      break;
    case BoardType::kSymmetricCircles:
    case BoardType::kAsymmetricCircles:
      std::snprintf(buf, sizeof(buf), "%s:%dx%d:%g:%g", type == BoardType::kSymmetricCircles ? "circles" : "acircles",
                    cols, rows, square_mm, CircleDiameterMm());
      break;
    case BoardType::kCharuco:
      std::snprintf(buf, sizeof(buf), "charuco:%dx%d:%g:%g:%s", cols, rows, square_mm, marker_mm, dictionary.c_str());
      break;
  }
  return buf;
}

BoardSpec ParseBoardSpec(const std::string& text, const InputLocation& where) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t colon = text.find(':', start);
    parts.push_back(text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  BoardSpec b;
  const std::string& kind = parts[0];
  if (kind == "chessboard") {
    b.type = BoardType::kChessboard;
  } else if (kind == "circles") {
    b.type = BoardType::kSymmetricCircles;
  } else if (kind == "acircles") {
    b.type = BoardType::kAsymmetricCircles;
  } else if (kind == "charuco") {
    b.type = BoardType::kCharuco;
  } else {
    throw InputError(where, "unknown board kind '" + kind + "' (chessboard, circles, acircles, charuco)");
  }
  const std::size_t min_parts = b.type == BoardType::kCharuco ? 4 : 3;
  const std::size_t max_parts = b.type == BoardType::kChessboard ? 3 : b.type == BoardType::kCharuco ? 5 : 4;
  if (parts.size() < min_parts || parts.size() > max_parts) {
    throw InputError(where,
                     "expected e.g. chessboard:9x6:25, circles:4x11:20, acircles:4x11:20, "
                     "charuco:10x7:25:18:DICT_5X5_100; got '" +
                         text + "'");
  }
  const std::size_t x = parts[1].find('x');
  if (x == std::string::npos) throw InputError(where, "board size must read COLSxROWS, got '" + parts[1] + "'");
  b.cols = static_cast<int>(ParseDouble(parts[1].substr(0, x), where));
  b.rows = static_cast<int>(ParseDouble(parts[1].substr(x + 1), where));
  b.square_mm = ParseDouble(parts[2], where);
  if (b.type == BoardType::kCharuco) {
    b.marker_mm = ParseDouble(parts[3], where);
    if (parts.size() == 5) b.dictionary = parts[4];
  } else if (parts.size() == 4) {
    b.circle_diameter_mm = ParseDouble(parts[3], where);
  }
  const std::string bad = b.Validate();
  if (!bad.empty()) throw InputError(where, bad);
  return b;
}

BoardSpec ReadBoardSpecArgument(const std::string& text_or_path, const std::string& option) {
  if (!std::filesystem::is_regular_file(text_or_path)) return ParseBoardSpec(text_or_path, {"", 0, option});
  const std::string contents = ReadTextFile(text_or_path);
  std::size_t start = 0;
  int line = 0;
  while (start < contents.size()) {
    const std::size_t end = std::min(contents.find('\n', start), contents.size());
    std::string l = contents.substr(start, end - start);
    ++line;
    l.erase(0, l.find_first_not_of(" \t\r"));
    l.erase(l.find_last_not_of(" \t\r") + 1);
    if (!l.empty() && l[0] != '#') return ParseBoardSpec(l, {text_or_path, line, "board"});
    start = end + 1;
  }
  throw InputError({text_or_path, 0, "board"}, "no board description in the file");
}

std::vector<std::string> ListBoardImages(const std::string& folder) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(folder)) throw InputError({folder, 0, ""}, "not a folder of images");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(folder)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png" || ext == ".bmp" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff") {
      files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError({folder, 0, ""}, "no images (png, bmp, jpg, tif) in the folder");
  return files;
}

std::vector<cv::Point3f> BoardObjectPoints(const BoardSpec& board) {
  std::vector<cv::Point3f> p;
  const float s = static_cast<float>(board.square_mm);
  switch (board.type) {
    case BoardType::kChessboard:
    case BoardType::kSymmetricCircles:
      for (int i = 0; i < board.rows; ++i) {
        for (int j = 0; j < board.cols; ++j) p.emplace_back(j * s, i * s, 0.0f);
      }
      break;
    case BoardType::kAsymmetricCircles:
      for (int i = 0; i < board.rows; ++i) {
        for (int j = 0; j < board.cols; ++j) p.emplace_back((2 * j + i % 2) * s, i * s, 0.0f);
      }
      break;
    case BoardType::kCharuco:
      p = internal::MakeCharucoBoard(board)->chessboardCorners;
      break;
  }
  return p;
}

std::string BoardDetectOptions::Validate() const {
  if (!(subpix_window_fraction > 0.0 && subpix_window_fraction < 0.5))
    return "subpix_window_fraction must be in (0, 0.5)";
  if (subpix_min_half_window < 1) return "subpix_min_half_window must be at least 1";
  if (min_charuco_corners < 4) return "min_charuco_corners must be at least 4";
  return "";
}

BoardDetection DetectBoard(const cv::Mat& gray, const BoardSpec& board, int min_charuco_corners) {
  BoardDetectOptions o;
  o.min_charuco_corners = min_charuco_corners;
  return DetectBoard(gray, board, o);
}

BoardDetection DetectBoard(const cv::Mat& gray, const BoardSpec& board, const BoardDetectOptions& options) {
  ThrowIfInvalid(options.Validate(), "BoardDetectOptions");
  BoardDetection d;
  const std::vector<cv::Point3f> all = BoardObjectPoints(board);
  const cv::Size pattern(board.cols, board.rows);
  std::vector<cv::Point2f> pts;
  const int min_charuco_corners = options.min_charuco_corners;
  switch (board.type) {
    case BoardType::kChessboard:
      // The classic detector with its fast check goes first: it decides quickly that a board is
      // absent, where the sector-based one searches for seconds. The sector-based detector then
      // gives the robust, ordered grid (≈0.03 px on rendered boards, against ≈0.08 px for
      // findChessboardCorners + a fixed 5×5 cornerSubPix); the classic one is the fallback.
      d.found = cv::findChessboardCorners(
          gray, pattern, pts, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
      if (d.found) {
        std::vector<cv::Point2f> accurate;
        const bool sb = cv::findChessboardCornersSB(gray, pattern, accurate, cv::CALIB_CB_ACCURACY);
        if (sb) pts = accurate;
        if (options.refinement == CornerRefinement::kSubPix) {
          if (sb) d.sector_points = pts;
          // The sector-based positions carry a geometry-fixed, board-wide correlated error that
          // biases calibrations beyond their reported σ; see CornerRefinement.
          RefineCornersAdaptive(gray, board.cols, board.rows, options, &pts);
        } else if (!sb) {
          cv::cornerSubPix(gray, pts, cv::Size(5, 5), cv::Size(-1, -1),
                           cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
        }
      }
      if (d.found && (board.cols + board.rows) % 2 == 1) {
        // Canonical order: the square enclosed by corners 0, 1, cols, cols+1 is dark (square
        // (0,0) of the board). With cols + rows odd the board is not 180° symmetric, so this fixes
        // the board frame in every camera.
        const cv::Point2f c = 0.25f * (pts[0] + pts[1] + pts[board.cols] + pts[board.cols + 1]);
        const cv::Point2f far = 0.25f * (pts[pts.size() - 1] + pts[pts.size() - 2] + pts[pts.size() - 1 - board.cols] +
                                         pts[pts.size() - 2 - board.cols]);
        auto at = [&](const cv::Point2f& p) {
          const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, gray.cols - 1);
          const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, gray.rows - 1);
          return static_cast<int>(gray.at<unsigned char>(y, x));
        };
        if (at(c) > at(far)) {
          std::reverse(pts.begin(), pts.end());
          std::reverse(d.sector_points.begin(), d.sector_points.end());
        }
      }
      break;
    case BoardType::kSymmetricCircles:
      d.found = cv::findCirclesGrid(gray, pattern, pts, cv::CALIB_CB_SYMMETRIC_GRID);
      break;
    case BoardType::kAsymmetricCircles:
      d.found = cv::findCirclesGrid(gray, pattern, pts, cv::CALIB_CB_ASYMMETRIC_GRID);
      break;
    case BoardType::kCharuco: {
      const cv::Ptr<cv::aruco::CharucoBoard> cb = internal::MakeCharucoBoard(board);
      std::vector<std::vector<cv::Point2f>> marker_corners;
      std::vector<int> marker_ids;
      cv::aruco::detectMarkers(gray, cb->dictionary, marker_corners, marker_ids);
      if (marker_ids.empty()) {
        d.reason = "no ArUco markers found";
        return d;
      }
      std::vector<int> ids;
      cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, cb, pts, ids);
      if (static_cast<int>(ids.size()) < min_charuco_corners) {
        d.reason = "only " + std::to_string(ids.size()) + " ChArUco corners found";
        return d;
      }
      d.found = true;
      d.ids = ids;
      break;
    }
  }
  if (!d.found) {
    if (d.reason.empty()) d.reason = "board not found";
    return d;
  }
  if (d.ids.empty()) {
    for (int i = 0; i < static_cast<int>(pts.size()); ++i) d.ids.push_back(i);
  }
  d.image_points = pts;
  for (int id : d.ids) d.object_points.push_back(all[id]);
  return d;
}

}  // namespace ramtk::calib
