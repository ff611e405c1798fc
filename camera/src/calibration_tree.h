#pragma once
// The text of a stereo calibration file as a small tree (internal to the camera module).
//
// OpenCV writes calibration files in two dialects: YAML with a `%YAML:1.0` first line and
// `!!opencv-matrix` maps, and JSON with `"type_id": "opencv-matrix"` maps. cv::FileStorage's YAML
// parser in OpenCV 4.6 hangs on some malformed files (a finding of
// fuzz/fuzz_stereo_calibration.cpp, kept in fuzz/known_hangs/), so the text is parsed by
// yaml-cpp (YAML) or nlohmann-json (JSON) into this tree, which remembers each node's line for
// error messages. OpenCV's XML (first non-blank character '<') is read by cv::FileStorage; its
// nodes carry no line.

#include <string>
#include <utility>
#include <vector>

namespace ramtk::camera::internal {

struct CalibrationNode {
  enum class Kind { kNull, kNumber, kText, kList, kMap };
  Kind kind = Kind::kNull;
  double number = 0.0;                                          // kNumber
  bool integer = false;                                         // kNumber written without a fraction or exponent
  std::string text;                                             // kText
  std::vector<CalibrationNode> items;                           // kList
  std::vector<std::pair<std::string, CalibrationNode>> fields;  // kMap, in file order
  int line = 0;                                                 // 1-based line in the file (0 when unknown, e.g. JSON)

  // The field `key` of a map, or nullptr (also for a node that is not a map).
  const CalibrationNode* Find(const std::string& key) const;
};

// Limits on what a calibration file may be: a few kB in practice.
inline constexpr std::size_t kMaxCalibrationFileBytes = 4u << 20;  // 4 MiB
inline constexpr int kMaxCalibrationDepth = 16;                    // nesting of lists / maps

// Parses YAML (OpenCV's dialect or plain YAML), JSON (first non-blank character '{') or OpenCV's
// XML (first non-blank character '<'). Throws InputError naming `path` (and the line where known)
// on a parse error, a duplicate key, nesting deeper than kMaxCalibrationDepth or a file over
// kMaxCalibrationFileBytes.
CalibrationNode ParseCalibrationTree(const std::string& text, const std::string& path);

}  // namespace ramtk::camera::internal
