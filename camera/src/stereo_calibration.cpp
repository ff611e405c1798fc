#include "ramtk/camera/stereo_calibration.h"

#include <cmath>
#include <exception>
#include <fstream>
#include <optional>
#include <opencv2/core.hpp>
#include <sstream>
#include <utility>

#include "calibration_tree.h"
#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace ramtk::camera {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

using internal::CalibrationNode;
using Kind = CalibrationNode::Kind;

// Where a node is: the file, its line when known, the key.
InputLocation At(const std::string& path, const CalibrationNode& node, const std::string& key) {
  return {path, node.line, key};
}

// Reads a matrix node (an opencv-matrix map or a plain list of numbers, or one number) as doubles,
// row-major. Returns false if the key is absent or null.
bool ReadNumbers(const CalibrationNode* node, const std::string& path, const std::string& key,
                 std::vector<double>* values, int* rows, int* cols) {
  if (node == nullptr || node->kind == Kind::kNull) return false;
  values->clear();
  auto numbers = [&](const CalibrationNode& list) {
    for (const CalibrationNode& item : list.items) {
      if (item.kind != Kind::kNumber) throw InputError(At(path, item, key), "expected a list of numbers");
      values->push_back(item.number);
    }
  };
  switch (node->kind) {
    case Kind::kNumber:
      values->push_back(node->number);
      *rows = *cols = 1;
      return true;
    case Kind::kList:
      // [[a, b, c], [d, e, f], ...] is a matrix by rows; a flat list is a column.
      if (!node->items.empty() && node->items.front().kind == Kind::kList) {
        const std::size_t n = node->items.front().items.size();
        for (const CalibrationNode& row : node->items) {
          if (row.kind != Kind::kList || row.items.size() != n)
            throw InputError(At(path, row, key), "expected rows of equal length");
          numbers(row);
        }
        *rows = static_cast<int>(node->items.size());
        *cols = static_cast<int>(n);
        return true;
      }
      numbers(*node);
      *rows = static_cast<int>(values->size());
      *cols = 1;
      return true;
    case Kind::kMap: {
      // An opencv-matrix: rows, cols, dt, data. The declared size is checked against the data
      // (calibration matrices are at most 3x3 or a few dozen values).
      const CalibrationNode* r = node->Find("rows");
      const CalibrationNode* c = node->Find("cols");
      const CalibrationNode* data = node->Find("data");
      if (r == nullptr || c == nullptr || data == nullptr || r->kind != Kind::kNumber || !r->integer ||
          c->kind != Kind::kNumber || !c->integer || data->kind != Kind::kList)
        throw InputError(At(path, *node, key),
                         "not a matrix: an opencv-matrix needs integer rows and cols and a data list");
      const double nr = r->number, nc = c->number;
      if (!(nr >= 1 && nc >= 1 && nr <= 64 && nc <= 64) || nr * nc != static_cast<double>(data->items.size()))
        throw InputError(At(path, *node, key), "not a matrix: " + std::to_string(static_cast<long long>(nr)) + "x" +
                                                   std::to_string(static_cast<long long>(nc)) + " with " +
                                                   std::to_string(data->items.size()) +
                                                   " values (rows and cols must be 1..64 and match the data)");
      numbers(*data);
      *rows = static_cast<int>(nr);
      *cols = static_cast<int>(nc);
      return true;
    }
    default:
      throw InputError(At(path, *node, key), "expected a number, a list of numbers or an opencv-matrix");
  }
}

std::vector<double> RequireNumbers(const CalibrationNode& root, const std::string& path,
                                   const std::vector<std::string>& keys, int* rows, int* cols, std::string* used_key) {
  std::vector<double> values;
  for (const std::string& key : keys) {
    const CalibrationNode* node = root.Find(key);
    if (ReadNumbers(node, path, key, &values, rows, cols)) {
      *used_key = key;
      for (double v : values)
        if (!std::isfinite(v)) throw InputError(At(path, *node, key), "contains a non-finite value");
      return values;
    }
  }
  std::string names;
  for (const std::string& key : keys) names += (names.empty() ? "" : " or ") + key;
  throw InputError({path, 0, keys.front()}, "missing key (expected " + names + ")");
}

int LineOf(const CalibrationNode& root, const std::string& key) {
  const CalibrationNode* node = root.Find(key);
  return node == nullptr ? 0 : node->line;
}

// The lens model of camera `suffix` ("1" or "2"): distortion_model<suffix>, else distortion_model,
// else the 5-coefficient or rational model as the coefficient vector says.
LensModel ReadLensModel(const CalibrationNode& fs, const std::string& path, const std::string& suffix) {
  for (const std::string key : {"distortion_model" + suffix, std::string("distortion_model")}) {
    const CalibrationNode* node = fs.Find(key);
    if (node == nullptr || node->kind == Kind::kNull) continue;
    LensModel model = LensModel::kPinhole5;
    if (node->kind != Kind::kText || !ParseLensModel(node->text, &model))
      throw InputError(At(path, *node, key), "unknown lens model (expected pinhole5, rational, thin-prism or fisheye)");
    return model;
  }
  return LensModel::kPinhole5;
}

// The sampling kernel of camera `suffix` ("1", "2" or ""): sampling_kernel<suffix>, else
// sampling_kernel (both cameras), a map {fill_factor, psf_sigma_px}; not stated when absent.
std::optional<SamplingKernel> ReadSamplingKernel(const CalibrationNode& fs, const std::string& path,
                                                 const std::string& suffix) {
  for (const std::string& key : {"sampling_kernel" + suffix, std::string("sampling_kernel")}) {
    const CalibrationNode* node = fs.Find(key);
    if (node == nullptr || node->kind == Kind::kNull) continue;
    if (node->kind != Kind::kMap)
      throw InputError(At(path, *node, key), "expected a map {fill_factor, psf_sigma_px}");
    SamplingKernel kernel;
    for (const auto& [name, value] : {std::pair<const char*, double*>{"fill_factor", &kernel.fill_factor},
                                      {"psf_sigma_px", &kernel.psf_sigma_px}}) {
      const CalibrationNode* field = node->Find(name);
      if (field == nullptr || field->kind != Kind::kNumber)
        throw InputError(At(path, *node, key + "." + name), "missing or not a number");
      *value = field->number;
    }
    const std::string error = kernel.Validate();
    if (!error.empty()) throw InputError(At(path, *node, key), error);
    return kernel;
  }
  return std::nullopt;
}

CameraIntrinsics ReadCamera(const CalibrationNode& fs, const std::string& path, const std::string& k_key,
                            const std::string& k_alias, const std::string& d_key, const std::string& suffix) {
  int rows = 0, cols = 0;
  std::string key;
  const std::vector<double> k = RequireNumbers(fs, path, {k_key, k_alias}, &rows, &cols, &key);
  const InputLocation k_at{path, LineOf(fs, key), key};
  if (rows == 9 && cols == 1) rows = cols = 3;  // a flat list of 9, row-major
  if (rows != 3 || cols != 3)
    throw InputError(k_at, "expected a 3x3 camera matrix, got " + std::to_string(rows) + "x" + std::to_string(cols));
  if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || std::abs(k[8] - 1.0) > 1e-12)
    throw InputError(k_at, "not a pinhole camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (skew unsupported)");
  if (!(k[0] > 0.0 && k[4] > 0.0)) throw InputError(k_at, "focal lengths must be positive");
  CameraIntrinsics cam;
  cam.fx = k[0];
  cam.cx = k[2];
  cam.fy = k[4];
  cam.cy = k[5];
  const std::vector<double> d = RequireNumbers(fs, path, {d_key}, &rows, &cols, &key);
  const InputLocation d_at{path, LineOf(fs, key), key};
  if (std::min(rows, cols) != 1)
    throw InputError(d_at, "expected the distortion coefficients in one row, got " + std::to_string(rows) + "x" +
                               std::to_string(cols));
  const LensModel model = ReadLensModel(fs, path, suffix);
  if (model != LensModel::kFisheye && d.size() != 4 && d.size() != 5 && d.size() != 8 && d.size() != 12 &&
      d.size() != 14)
    throw InputError(d_at, "expected 4, 5, 8, 12 or 14 distortion coefficients in one row, got " +
                               std::to_string(rows) + "x" + std::to_string(cols));
  const std::string error = DistortionFromVector(d, model, &cam.distortion);
  if (!error.empty()) throw InputError(d_at, error);
  cam.sampling_kernel = ReadSamplingKernel(fs, path, suffix);
  return cam;
}

// Image size [w, h] from image_size / S / image_width+image_height.
void ReadImageSize(const CalibrationNode& fs, const std::string& path, const std::vector<std::string>& keys, int* width,
                   int* height) {
  std::vector<double> v;
  int rows = 0, cols = 0;
  for (const std::string& key : keys) {
    if (ReadNumbers(fs.Find(key), path, key, &v, &rows, &cols)) {
      const InputLocation at{path, LineOf(fs, key), key};
      if (v.size() != 2) throw InputError(at, "expected the image size as [width, height]");
      if (!(v[0] >= 1 && v[0] <= 1e6 && v[1] >= 1 && v[1] <= 1e6) || v[0] != std::floor(v[0]) ||
          v[1] != std::floor(v[1]))
        throw InputError(at, "image size must be two positive integers (at most 1000000)");
      *width = static_cast<int>(v[0]);
      *height = static_cast<int>(v[1]);
      return;
    }
  }
  std::vector<double> w, h;
  if (ReadNumbers(fs.Find("image_width"), path, "image_width", &w, &rows, &cols) &&
      ReadNumbers(fs.Find("image_height"), path, "image_height", &h, &rows, &cols) && w.size() == 1 && h.size() == 1) {
    if (!(w[0] >= 1 && w[0] <= 1e6 && h[0] >= 1 && h[0] <= 1e6) || w[0] != std::floor(w[0]) || h[0] != std::floor(h[0]))
      throw InputError({path, LineOf(fs, "image_width"), "image_width"},
                       "image size must be two positive integers (at most 1000000)");
    *width = static_cast<int>(w[0]);
    *height = static_cast<int>(h[0]);
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
  RequireRegularFile(path);  // before the probe: opening a FIFO would block
  {
    std::ifstream probe(path);
    if (!probe) throw InputError({path, 0, ""}, "cannot open stereo calibration file");
  }
  return ParseStereoCalibration(ReadTextFile(path), path);
}

namespace {
StereoCalibration ReadCalibrationKeys(const CalibrationNode& fs, const std::string& path);
}  // namespace

StereoCalibration ParseStereoCalibration(const std::string& text, const std::string& path) {
  const CalibrationNode root = internal::ParseCalibrationTree(text, path);
  // The keys are looked up by name: a top level that is a list or a scalar has none.
  if (root.kind != Kind::kMap)
    throw InputError({path, root.line, ""}, "the top level is not a map of keys (K1, D1, R, T, ...)");
  StereoCalibration calibration = ReadCalibrationKeys(root, path);
  calibration.source_path = path;
  return calibration;
}

namespace {

StereoCalibration ReadCalibrationKeys(const CalibrationNode& fs, const std::string& path) {
  StereoCalibration calib;
  calib.left = ReadCamera(fs, path, "K1", "M1", "D1", "1");
  calib.right = ReadCamera(fs, path, "K2", "M2", "D2", "2");
  ReadImageSize(fs, path, {"image_size", "S", "imageSize"}, &calib.left.width, &calib.left.height);
  calib.right.width = calib.left.width;
  calib.right.height = calib.left.height;
  if (fs.Find("image_size2") != nullptr)
    ReadImageSize(fs, path, {"image_size2"}, &calib.right.width, &calib.right.height);

  int rows = 0, cols = 0;
  std::string key;
  const std::vector<double> r = RequireNumbers(fs, path, {"R", "Rlr"}, &rows, &cols, &key);
  if (rows == 9 && cols == 1) rows = cols = 3;  // a flat list of 9, row-major
  if (rows != 3 || cols != 3)
    throw InputError({path, LineOf(fs, key), key},
                     "expected a 3x3 rotation, got " + std::to_string(rows) + "x" + std::to_string(cols));
  Mat3 rotation;
  for (int i = 0; i < 9; ++i) rotation(i / 3, i % 3) = r[i];
  const double ortho = OrthonormalityError(rotation);
  if (!(ortho <= kMaxRotationOrthonormalityError))
    throw InputError({path, LineOf(fs, key), key}, "not a rotation: orthonormality error " + FormatDouble(ortho) +
                                                       " (max(|RᵀR − I|, |det R − 1|) must be below " +
                                                       FormatDouble(kMaxRotationOrthonormalityError) + ")");
  const std::vector<double> t = RequireNumbers(fs, path, {"T", "Tlr"}, &rows, &cols, &key);
  if (t.size() != 3 || std::min(rows, cols) != 1)
    throw InputError({path, LineOf(fs, key), key},
                     "expected a 3-vector translation (mm), got " + std::to_string(rows) + "x" + std::to_string(cols));
  calib.right_from_left.linear() = rotation;
  calib.right_from_left.translation() = Vec3(t[0], t[1], t[2]);
  // A stereo pair triangulates along its baseline: zero (or a corrupt huge value) cannot be a rig.
  const double baseline = calib.right_from_left.translation().norm();
  if (!(baseline >= 1e-3 && baseline <= 1e5)) {
    throw InputError({path, LineOf(fs, key), key}, "stereo baseline |T| = " + FormatDouble(baseline) +
                                                       " mm is not a stereo rig (expected 0.001 .. 100000 mm)");
  }

  std::vector<double> v;
  if (ReadNumbers(fs.Find("rms_px"), path, "rms_px", &v, &rows, &cols) && v.size() == 1) calib.rms_px = v[0];
  if (ReadNumbers(fs.Find("per_view_errors_px"), path, "per_view_errors_px", &v, &rows, &cols))
    calib.per_view_errors_px = v;
  if (ReadNumbers(fs.Find("parameter_std"), path, "parameter_std", &v, &rows, &cols)) calib.parameter_std = v;
  // The keys `ramtk calib cameras` writes (calib/src/calibration_file.cpp): rms, per_view_errors
  // (left, right per pair) and the σ blocks std_intrinsics1/2, std_R, std_T, which become
  // parameter_std in the order of kCalibParameterStdOrder.
  if (!std::isfinite(calib.rms_px) && ReadNumbers(fs.Find("rms"), path, "rms", &v, &rows, &cols) && v.size() == 1)
    calib.rms_px = v[0];
  if (calib.per_view_errors_px.empty() &&
      ReadNumbers(fs.Find("per_view_errors"), path, "per_view_errors", &v, &rows, &cols))
    calib.per_view_errors_px = v;
  if (calib.parameter_std.empty()) {
    std::vector<double> all, block;
    bool complete = true;
    for (const auto& [key, n] :
         {std::pair<const char*, size_t>{"std_intrinsics1", 9}, {"std_intrinsics2", 9}, {"std_R", 3}, {"std_T", 3}}) {
      if (!ReadNumbers(fs.Find(key), path, key, &block, &rows, &cols) || block.size() != n) {
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

namespace {

void WriteCameraKeys(cv::FileStorage& fs, const CameraIntrinsics& c, const std::string& suffix) {
  const Mat3 kk = c.K();
  cv::Mat k(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) k.at<double>(i, j) = kk(i, j);
  const std::vector<double> d = DistortionVector(c.distortion);
  fs << ("K" + suffix) << k << ("D" + suffix) << cv::Mat(d, true).reshape(1, 1);
  if (c.distortion.model != LensModel::kPinhole5)
    fs << ("distortion_model" + suffix) << LensModelName(c.distortion.model);
  if (c.sampling_kernel) {
    fs << ("sampling_kernel" + suffix) << "{" << "fill_factor" << c.sampling_kernel->fill_factor << "psf_sigma_px"
       << c.sampling_kernel->psf_sigma_px << "}";
  }
}

void WriteQualityKeys(cv::FileStorage& fs, double rms_px, const std::vector<double>& per_view_errors_px,
                      const std::vector<double>& parameter_std) {
  if (std::isfinite(rms_px)) fs << "rms_px" << rms_px;
  if (!per_view_errors_px.empty()) fs << "per_view_errors_px" << per_view_errors_px;
  if (!parameter_std.empty()) fs << "parameter_std" << parameter_std;
}

cv::FileStorage MemoryStorage(CalibrationFormat format, const std::string& comment) {
  const char* name = format == CalibrationFormat::kJson ? ".json" : format == CalibrationFormat::kXml ? ".xml" : ".yml";
  cv::FileStorage fs(name, cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  if (format != CalibrationFormat::kJson && !comment.empty()) fs.writeComment(comment);
  return fs;
}

}  // namespace

CalibrationFormat CalibrationFormatOf(const std::string& path) {
  if (EndsWith(path, ".json")) return CalibrationFormat::kJson;
  if (EndsWith(path, ".xml")) return CalibrationFormat::kXml;
  return CalibrationFormat::kYaml;
}

std::string StereoCalibrationText(const StereoCalibration& calib, bool json, const std::string& comment,
                                  const ExtraCalibrationKeys& extra_keys) {
  return StereoCalibrationText(calib, json ? CalibrationFormat::kJson : CalibrationFormat::kYaml, comment, extra_keys);
}

std::string StereoCalibrationText(const StereoCalibration& calib, CalibrationFormat format, const std::string& comment,
                                  const ExtraCalibrationKeys& extra_keys) {
  cv::FileStorage fs = MemoryStorage(format, comment);
  fs << "image_size" << cv::Size(calib.left.width, calib.left.height);
  if (calib.right.width != calib.left.width || calib.right.height != calib.left.height)
    fs << "image_size2" << cv::Size(calib.right.width, calib.right.height);
  WriteCameraKeys(fs, calib.left, "1");
  WriteCameraKeys(fs, calib.right, "2");
  cv::Mat r(3, 3, CV_64F), t(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.at<double>(i, j) = calib.right_from_left.linear()(i, j);
    t.at<double>(i) = calib.right_from_left.translation()(i);
  }
  fs << "R" << r << "T" << t;
  WriteQualityKeys(fs, calib.rms_px, calib.per_view_errors_px, calib.parameter_std);
  if (extra_keys) extra_keys(fs);
  return fs.releaseAndGetString();
}

std::string CameraCalibrationText(const CameraIntrinsics& camera, double rms_px,
                                  const std::vector<double>& per_view_errors_px,
                                  const std::vector<double>& parameter_std, const std::string& comment,
                                  const ExtraCalibrationKeys& extra_keys, CalibrationFormat format) {
  cv::FileStorage fs = MemoryStorage(format, comment);
  fs << "image_size" << cv::Size(camera.width, camera.height);
  WriteCameraKeys(fs, camera, "1");
  WriteQualityKeys(fs, rms_px, per_view_errors_px, parameter_std);
  if (extra_keys) extra_keys(fs);
  return fs.releaseAndGetString();
}

void WriteStereoCalibration(const std::string& path, const StereoCalibration& calib) {
  WriteFileAtomically(path, StereoCalibrationText(calib, CalibrationFormatOf(path),
                                                  "ramtk stereo calibration: x_in_right = R * x_in_left + T, T in mm, "
                                                  "pixels for K"));
}

}  // namespace ramtk::camera

namespace ramtk::camera {

CameraIntrinsics ReadCameraCalibration(const std::string& path) {
  RequireRegularFile(path);
  const CalibrationNode root = internal::ParseCalibrationTree(ReadTextFile(path), path);
  if (root.kind != Kind::kMap)
    throw InputError({path, root.line, ""}, "the top level is not a map of keys (K1, D1, image_size, ...)");
  const bool opencv_sample = root.Find("K1") == nullptr && root.Find("M1") == nullptr &&
                             root.Find("camera_matrix") != nullptr;
  CameraIntrinsics camera = opencv_sample ? ReadCamera(root, path, "camera_matrix", "K", "distortion_coefficients", "")
                                          : ReadCamera(root, path, "K1", "M1", "D1", "1");
  ReadImageSize(root, path, {"image_size", "S", "imageSize"}, &camera.width, &camera.height);
  return camera;
}

}  // namespace ramtk::camera
