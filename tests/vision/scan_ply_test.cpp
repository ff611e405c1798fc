// The PLY writer against PCL's reader (a peer library), and the reader's errors.
#include <gtest/gtest.h>
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace ramtk::vision {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + std::to_string(::getpid()) + ".ply")).string();
}

PointCloud ThreePoints() {
  PointCloud c;
  c.points_in_left = {{1.5f, -2.25f, 700.125f}, {0, 0, 0}, {-1e3f, 3.0e-3f, 1e4f}};
  c.sigma_mm = {0.01f, 0.02f, 0.5f};
  c.quality = {50, 1, 7.5f};
  return c;
}

TEST(ScanPly, PclReadsWhatWeWrite) {
  const std::string path = TempPath("ramtk_ply_");
  const PointCloud c = ThreePoints();
  WritePly(path, c, "test cloud");
  pcl::PointCloud<pcl::PointXYZ> xyz;
  ASSERT_EQ(pcl::io::loadPLYFile(path, xyz), 0);
  ASSERT_EQ(xyz.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(xyz[i].x, c.points_in_left[i].x());
    EXPECT_EQ(xyz[i].y, c.points_in_left[i].y());
    EXPECT_EQ(xyz[i].z, c.points_in_left[i].z());
  }
  // The extra properties are named fields PCL sees as float32.
  pcl::PCLPointCloud2 blob;
  ASSERT_EQ(pcl::io::loadPLYFile(path, blob), 0);
  std::vector<std::string> names;
  for (const auto& f : blob.fields) names.push_back(f.name);
  EXPECT_NE(std::find(names.begin(), names.end(), "sigma"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "quality"), names.end());
  for (const auto& f : blob.fields)
    if (f.name == "sigma") {
      EXPECT_EQ(f.datatype, pcl::PCLPointField::FLOAT32);
      float s;
      std::memcpy(&s, &blob.data[2 * blob.point_step + f.offset], 4);
      EXPECT_EQ(s, 0.5f);
    }
  // And our own reader round-trips exactly.
  const PointCloud back = ReadPly(path);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back.points_in_left, c.points_in_left);
  EXPECT_EQ(back.sigma_mm, c.sigma_mm);
  EXPECT_EQ(back.quality, c.quality);
  std::filesystem::remove(path);
}

TEST(ScanPly, ReadsPclsAsciiOutput) {
  const std::string path = TempPath("ramtk_ply_ascii_");
  pcl::PointCloud<pcl::PointXYZ> xyz;
  xyz.push_back({1, 2, 3});
  xyz.push_back({-4, 5.5f, 600});
  ASSERT_EQ(pcl::io::savePLYFileASCII(path, xyz), 0);
  const PointCloud back = ReadPly(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.points_in_left[1], Eigen::Vector3f(-4, 5.5f, 600));
  std::filesystem::remove(path);
}

TEST(ScanPly, TruncatedFileIsAnErrorNamingTheFile) {
  const std::string path = TempPath("ramtk_ply_cut_");
  std::string bytes = PlyBytes(ThreePoints());
  bytes.resize(bytes.size() - 7);
  std::ofstream(path, std::ios::binary) << bytes;
  try {
    ReadPly(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("file ends after 2 of 3 vertices"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(ScanPly, MismatchedSigmaIsRejected) {
  PointCloud c = ThreePoints();
  c.sigma_mm.pop_back();
  EXPECT_THROW(PlyBytes(c), InputError);
}

}  // namespace
}  // namespace ramtk::vision
