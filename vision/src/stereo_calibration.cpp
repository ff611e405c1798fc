#include "ramtk/vision/stereo_calibration.h"

#include <cmath>
#include <exception>
#include <utility>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace ramtk::vision {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Reads a matrix node (an opencv-matrix or a plain sequence of numbers) as doubles, row-major.
// Returns false if the key is absent.
bool ReadNumbers(const cv::FileNode& node, const std::string& path, const std::string& key, std::vector<double>* values,
                 int* rows, int* cols) {
  if (node.empty() || node.isNone()) return false;
  values->clear();
  if (node.isSeq()) {
    for (const auto& item : node) {
      if (!item.isReal() && !item.isInt()) throw InputError({path, 0, key}, "expected a list of numbers");
      values->push_back(static_cast<double>(item));
    }
    *rows = static_cast<int>(values->size());
    *cols = 1;
    return true;
  }
  if (node.isReal() || node.isInt()) {
    values->push_back(static_cast<double>(node));
    *rows = *cols = 1;
    return true;
  }
  // An opencv-matrix's declared size is checked before OpenCV allocates it: a corrupt "rows: s"
  // read as a huge count made it allocate gigabytes (found by fuzz/fuzz_stereo_calibration.cpp).
  // Calibration matrices are at most 3x3 or a few dozen values.
  if (node.isMap()) {
    const cv::FileNode r = node["rows"], c = node["cols"], data = node["data"];
    if (!r.isInt() || !c.isInt() || !data.isSeq())
      throw InputError({path, 0, key}, "not a matrix: an opencv-matrix needs integer rows and cols and a data list");
    const int nr = static_cast<int>(r), nc = static_cast<int>(c);
    if (nr < 1 || nc < 1 || nr > 64 || nc > 64 || static_cast<std::size_t>(nr) * nc != data.size())
      throw InputError({path, 0, key}, "not a matrix: " + std::to_string(nr) + "x" + std::to_string(nc) + " with " +
                                           std::to_string(data.size()) +
                                           " values (rows and cols must be 1..64 and match the data)");
  }
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception& e) {
    throw InputError({path, 0, key}, "not a matrix: " + std::string(e.what()));
  }
  if (m.empty()) throw InputError({path, 0, key}, "not a matrix, or an empty one");
  cv::Mat d;
  m.convertTo(d, CV_64F);
  *rows = d.rows;
  *cols = d.cols;
  for (int r = 0; r < d.rows; ++r)
    for (int c = 0; c < d.cols; ++c) values->push_back(d.at<double>(r, c));
  return true;
}

std::vector<double> RequireNumbers(const cv::FileStorage& fs, const std::string& path,
                                   const std::vector<std::string>& keys, int* rows, int* cols, std::string* used_key) {
  std::vector<double> values;
  for (const std::string& key : keys) {
    if (ReadNumbers(fs[key], path, key, &values, rows, cols)) {
      *used_key = key;
      for (double v : values)
        if (!std::isfinite(v)) throw InputError({path, 0, key}, "contains a non-finite value");
      return values;
    }
  }
  std::string names;
  for (const std::string& key : keys) names += (names.empty() ? "" : " or ") + key;
  throw InputError({path, 0, keys.front()}, "missing key (expected " + names + ")");
}

CameraIntrinsics ReadCamera(const cv::FileStorage& fs, const std::string& path, const std::string& k_key,
                            const std::string& k_alias, const std::string& d_key) {
  int rows = 0, cols = 0;
  std::string key;
  const std::vector<double> k = RequireNumbers(fs, path, {k_key, k_alias}, &rows, &cols, &key);
  if (rows != 3 || cols != 3)
    throw InputError({path, 0, key},
                     "expected a 3x3 camera matrix, got " + std::to_string(rows) + "x" + std::to_string(cols));
  if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || std::abs(k[8] - 1.0) > 1e-12)
    throw InputError({path, 0, key}, "not a pinhole camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (skew unsupported)");
  if (!(k[0] > 0.0 && k[4] > 0.0)) throw InputError({path, 0, key}, "focal lengths must be positive");
  CameraIntrinsics cam;
  cam.fx = k[0];
  cam.cx = k[2];
  cam.fy = k[4];
  cam.cy = k[5];
  const std::vector<double> d = RequireNumbers(fs, path, {d_key}, &rows, &cols, &key);
  if (std::min(rows, cols) != 1 ||
      (d.size() != 4 && d.size() != 5 && d.size() != 8 && d.size() != 12 && d.size() != 14))
    throw InputError({path, 0, key}, "expected 4, 5, 8, 12 or 14 distortion coefficients in one row, got " +
                                         std::to_string(rows) + "x" + std::to_string(cols));
  for (std::size_t i = 5; i < d.size(); ++i)
    if (d[i] != 0.0)
      throw InputError({path, 0, key}, "coefficient " + std::to_string(i) +
                                           " is not zero: only the 5-coefficient model (k1 k2 p1 p2 k3) is supported");
  cam.distortion = {d[0], d[1], d[2], d[3], d.size() > 4 ? d[4] : 0.0};
  return cam;
}

// Image size [w, h] from image_size / S / image_width+image_height.
void ReadImageSize(const cv::FileStorage& fs, const std::string& path, const std::vector<std::string>& keys, int* width,
                   int* height) {
  std::vector<double> v;
  int rows = 0, cols = 0;
  for (const std::string& key : keys) {
    if (ReadNumbers(fs[key], path, key, &v, &rows, &cols)) {
      if (v.size() != 2) throw InputError({path, 0, key}, "expected the image size as [width, height]");
      *width = static_cast<int>(v[0]);
      *height = static_cast<int>(v[1]);
      if (*width <= 0 || *height <= 0 || v[0] != *width || v[1] != *height)
        throw InputError({path, 0, key}, "image size must be two positive integers");
      return;
    }
  }
  std::vector<double> w, h;
  if (ReadNumbers(fs["image_width"], path, "image_width", &w, &rows, &cols) &&
      ReadNumbers(fs["image_height"], path, "image_height", &h, &rows, &cols) && w.size() == 1 && h.size() == 1) {
    *width = static_cast<int>(w[0]);
    *height = static_cast<int>(h[0]);
    if (*width <= 0 || *height <= 0) throw InputError({path, 0, "image_width"}, "image size must be positive");
    return;
  }
  throw InputError({path, 0, keys.front()},
                   "missing key (expected the image size as image_size, S or "
                   "image_width + image_height)");
}

std::string FormatDouble(double v) {
  std::ostringstream s;
  s.precision(3);
  s << std::scientific << v;
  return s.str();
}

}  // namespace

StereoCalibration ReadStereoCalibration(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError({path, 0, ""}, "cannot open stereo calibration file");
  }
  return ParseStereoCalibration(ReadTextFile(path), path);
}

namespace {
StereoCalibration ReadCalibrationKeys(const cv::FileStorage& fs, const std::string& path);
}  // namespace

StereoCalibration ParseStereoCalibration(const std::string& text, const std::string& path) {
  cv::FileStorage fs;
  try {
    // OpenCV tells YAML, JSON and XML apart by their first characters.
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    throw InputError({path, 0, ""}, "cannot parse as OpenCV FileStorage YAML/JSON: " + std::string(e.err));
  } catch (const std::exception& e) {
    // OpenCV's parser lets std::length_error escape on some malformed files (found by
    // fuzz/fuzz_stereo_calibration.cpp): still bad input, not an internal error.
    throw InputError({path, 0, ""}, "cannot parse as OpenCV FileStorage YAML/JSON (" + std::string(e.what()) + ")");
  }
  if (!fs.isOpened()) throw InputError({path, 0, ""}, "cannot parse as OpenCV FileStorage YAML/JSON");
  // The keys are looked up by name: a top level that is a list or a scalar has none (OpenCV
  // would throw from the lookup; found by fuzz/fuzz_stereo_calibration.cpp).
  if (!fs.root().isMap()) throw InputError({path, 0, ""}, "the top level is not a map of keys (K1, D1, R, T, ...)");
  try {
    return ReadCalibrationKeys(fs, path);
  } catch (const cv::Exception& e) {
    throw InputError({path, 0, ""}, "unreadable value: " + std::string(e.err));
  }
}

namespace {

StereoCalibration ReadCalibrationKeys(const cv::FileStorage& fs, const std::string& path) {
  StereoCalibration calib;
  calib.left = ReadCamera(fs, path, "K1", "M1", "D1");
  calib.right = ReadCamera(fs, path, "K2", "M2", "D2");
  ReadImageSize(fs, path, {"image_size", "S", "imageSize"}, &calib.left.width, &calib.left.height);
  calib.right.width = calib.left.width;
  calib.right.height = calib.left.height;
  if (!fs["image_size2"].empty()) ReadImageSize(fs, path, {"image_size2"}, &calib.right.width, &calib.right.height);

  int rows = 0, cols = 0;
  std::string key;
  const std::vector<double> r = RequireNumbers(fs, path, {"R", "Rlr"}, &rows, &cols, &key);
  if (rows != 3 || cols != 3)
    throw InputError({path, 0, key},
                     "expected a 3x3 rotation, got " + std::to_string(rows) + "x" + std::to_string(cols));
  Mat3 rotation;
  for (int i = 0; i < 9; ++i) rotation(i / 3, i % 3) = r[i];
  const double ortho = OrthonormalityError(rotation);
  if (!(ortho <= kMaxRotationOrthonormalityError))
    throw InputError({path, 0, key}, "not a rotation: orthonormality error " + FormatDouble(ortho) +
                                         " (max(|RᵀR − I|, |det R − 1|) must be below " +
                                         FormatDouble(kMaxRotationOrthonormalityError) + ")");
  const std::vector<double> t = RequireNumbers(fs, path, {"T", "Tlr"}, &rows, &cols, &key);
  if (t.size() != 3 || std::min(rows, cols) != 1)
    throw InputError({path, 0, key},
                     "expected a 3-vector translation (mm), got " + std::to_string(rows) + "x" + std::to_string(cols));
  calib.right_from_left.linear() = rotation;
  calib.right_from_left.translation() = Vec3(t[0], t[1], t[2]);
  // A stereo pair triangulates along its baseline: zero (or a corrupt huge value) cannot be a rig.
  const double baseline = calib.right_from_left.translation().norm();
  if (!(baseline >= 1e-3 && baseline <= 1e5)) {
    throw InputError({path, 0, key}, "stereo baseline |T| = " + FormatDouble(baseline) +
                                         " mm is not a stereo rig (expected 0.001 .. 100000 mm)");
  }

  std::vector<double> v;
  if (ReadNumbers(fs["rms_px"], path, "rms_px", &v, &rows, &cols) && v.size() == 1) calib.rms_px = v[0];
  if (ReadNumbers(fs["per_view_errors_px"], path, "per_view_errors_px", &v, &rows, &cols)) calib.per_view_errors_px = v;
  if (ReadNumbers(fs["parameter_std"], path, "parameter_std", &v, &rows, &cols)) calib.parameter_std = v;
  // The keys `ramtk calib cameras` writes (calib/src/calibration_file.cpp): rms, per_view_errors
  // (left, right per pair) and the σ blocks std_intrinsics1/2, std_R, std_T, which become
  // parameter_std in the order of kCalibParameterStdOrder.
  if (!std::isfinite(calib.rms_px) && ReadNumbers(fs["rms"], path, "rms", &v, &rows, &cols) && v.size() == 1)
    calib.rms_px = v[0];
  if (calib.per_view_errors_px.empty() && ReadNumbers(fs["per_view_errors"], path, "per_view_errors", &v, &rows, &cols))
    calib.per_view_errors_px = v;
  if (calib.parameter_std.empty()) {
    std::vector<double> all, block;
    bool complete = true;
    for (const auto& [key, n] : {std::pair<const char*, size_t>{"std_intrinsics1", 9}, {"std_intrinsics2", 9},
                                 {"std_R", 3}, {"std_T", 3}}) {
      if (!ReadNumbers(fs[key], path, key, &block, &rows, &cols) || block.size() != n) {
        complete = false;
        break;
      }
      all.insert(all.end(), block.begin(), block.end());
    }
    if (complete) calib.parameter_std = all;
  }
  return calib;
}

}  // namespace

void WriteStereoCalibration(const std::string& path, const StereoCalibration& calib) {
  const bool json = EndsWith(path, ".json");
  cv::FileStorage fs(json ? ".json" : ".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  auto camera_matrix = [](const CameraIntrinsics& c) {
    cv::Mat k(3, 3, CV_64F);
    const Mat3 kk = c.K();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) k.at<double>(i, j) = kk(i, j);
    return k;
  };
  auto dist = [](const CameraIntrinsics& c) {
    const Distortion& d = c.distortion;
    return cv::Mat((cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3));
  };
  if (!json) fs.writeComment("ramtk stereo calibration: x_in_right = R * x_in_left + T, T in mm, pixels for K");
  fs << "image_size" << cv::Size(calib.left.width, calib.left.height);
  if (calib.right.width != calib.left.width || calib.right.height != calib.left.height)
    fs << "image_size2" << cv::Size(calib.right.width, calib.right.height);
  fs << "K1" << camera_matrix(calib.left) << "D1" << dist(calib.left);
  fs << "K2" << camera_matrix(calib.right) << "D2" << dist(calib.right);
  cv::Mat r(3, 3, CV_64F), t(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.at<double>(i, j) = calib.right_from_left.linear()(i, j);
    t.at<double>(i) = calib.right_from_left.translation()(i);
  }
  fs << "R" << r << "T" << t;
  if (std::isfinite(calib.rms_px)) fs << "rms_px" << calib.rms_px;
  if (!calib.per_view_errors_px.empty()) fs << "per_view_errors_px" << calib.per_view_errors_px;
  if (!calib.parameter_std.empty()) fs << "parameter_std" << calib.parameter_std;
  WriteFileAtomically(path, fs.releaseAndGetString());
}

}  // namespace ramtk::vision
