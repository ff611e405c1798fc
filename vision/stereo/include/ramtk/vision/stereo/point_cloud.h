#pragma once
// A triangulated point cloud and its file format (DESIGN.md "Point cloud"; docs/formats.md):
// binary little-endian PLY with float32 `x y z` in millimetres in the left-camera frame and
// optional float32 `sigma` (mm, standard deviation of the point along its left-camera ray) and
// `quality` (decoder modulation over its noise, dimensionless). PCL, Open3D and CloudCompare
// read it.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ramtk::vision {

struct PointCloud {
  std::vector<Eigen::Vector3f> points_in_left;  // mm, left-camera frame
  std::vector<float> sigma_mm;                  // per point, or empty
  std::vector<float> quality;                   // per point, or empty
  std::vector<Eigen::Vector2f> left_pixels;     // left-camera pixel of each point, or empty (not written)

  std::size_t size() const { return points_in_left.size(); }
  // Throws InputError (field "sigma" / "quality") if an optional array is neither empty nor of
  // the cloud's size. (A check of data; options structs use the Validate() contract of core/error.h.)
  void Check(const std::string& where = "") const;
};

// The PLY file's bytes (header + binary little-endian body) for a cloud.
std::string PlyBytes(const PointCloud& cloud, const std::string& comment = "");
// Writes `cloud` to `path` atomically (temporary file + rename).
void WritePly(const std::string& path, const PointCloud& cloud, const std::string& comment = "");
// Reads a PLY with a `vertex` element whose x, y, z (and optionally sigma, quality) properties
// are float or double, in binary little-endian or ASCII; other properties and elements are
// skipped. InputError naming the file and the offending header line or element otherwise.
PointCloud ReadPly(const std::string& path);

}  // namespace ramtk::vision
