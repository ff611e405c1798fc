// Manifests from a folder: the sequence spec, globs in natural order, and the checks (frame count,
// readable images, one size), on a folder of small images written here.
#include "ramtk/vision/fringe/manifest_builder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

namespace fs = std::filesystem;

// 19 frames 0.png … 18.png per camera (the SLMaster layout), 8×6 px.
fs::path WriteCapture(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ramtk_manifest_" + name);
  fs::remove_all(dir);
  for (const char* cam : {"L", "R"}) {
    fs::create_directories(dir / cam);
    for (int i = 0; i < 19; ++i)
      cv::imwrite((dir / cam / (std::to_string(i) + ".png")).string(), cv::Mat(6, 8, CV_8U, cv::Scalar(10 * i)));
  }
  return dir;
}

ManifestBuildOptions Options(const fs::path& dir) {
  ManifestBuildOptions o;
  o.folder = dir.string();
  o.sequence = "ps:12:64,cgc:7";
  o.projector_width = 1280, o.projector_height = 720;
  o.output = (dir / "manifest.json").string();
  return o;
}

TEST(ManifestSequence, SpecReadsEveryBlockKind) {
  const std::vector<SequenceBlock> s = ParseSequenceSpec("ps:12:64,cgc:7,gc:3,het:4:64:56", {});
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].ImageCount(), 12);
  EXPECT_EQ(s[1].ImageCount(), 7);
  EXPECT_TRUE(s[1].complementary);
  EXPECT_FALSE(s[2].complementary);
  EXPECT_EQ(s[3].ImageCount(), 8);
  EXPECT_EQ(SequenceSpec(s), "ps:12:64,cgc:7,gc:3,het:4:64:56");
  EXPECT_THROW(ParseSequenceSpec("ps:12", {}), InputError);
  EXPECT_THROW(ParseSequenceSpec("xx:3", {}), InputError);
}

TEST(ManifestGlob, ExpandsInNaturalOrder) {
  const fs::path dir = WriteCapture("glob");
  const std::vector<std::string> files = ExpandImageGlob("L/*.png", dir.string());
  ASSERT_EQ(files.size(), 19u);
  for (int i = 0; i < 19; ++i) EXPECT_EQ(files[i], "L/" + std::to_string(i) + ".png");
  EXPECT_TRUE(ExpandImageGlob("L/*.bmp", dir.string()).empty());
  // A manifest holding globs reads as the list.
  FringeManifest m = BuildFringeManifest(Options(dir));
  m.cameras["left"] = {"L/*.png"};
  m.cameras["right"] = {"R/1?.png", "R/[0-9].png"};  // 10..18, then 0..9
  WriteFringeManifest((dir / "glob.json").string(), m);
  const FringeManifest read = ReadFringeManifest((dir / "glob.json").string());
  EXPECT_EQ(read.cameras.at("left").front(), "L/0.png");
  EXPECT_EQ(read.cameras.at("left").back(), "L/18.png");
  EXPECT_EQ(read.cameras.at("right").front(), "R/10.png");
  EXPECT_EQ(read.cameras.at("right")[9], "R/0.png");
  fs::remove_all(dir);
}

TEST(ManifestBuild, DefaultFoldersAndTheChecks) {
  const fs::path dir = WriteCapture("build");
  ManifestBuildSummary summary;
  const FringeManifest m = BuildFringeManifest(Options(dir), &summary);
  ASSERT_EQ(m.cameras.size(), 2u);
  EXPECT_EQ(m.cameras.at("left")[10], "L/10.png");
  EXPECT_EQ(m.cameras.at("right")[2], "R/2.png");
  EXPECT_EQ(summary.width, 8);
  EXPECT_EQ(summary.height, 6);
  // A frame too few for the sequence.
  ManifestBuildOptions o = Options(dir);
  o.sequence = "ps:12:64,cgc:6";
  try {
    BuildFringeManifest(o);
    ADD_FAILURE() << "wrong frame count accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("19 files match 'L/*', the sequence ps:12:64,cgc:6 needs 18"),
              std::string::npos)
        << e.what();
  }
  // An image of another size, then an unreadable one.
  cv::imwrite((dir / "R" / "5.png").string(), cv::Mat(7, 8, CV_8U, cv::Scalar(0)));
  try {
    BuildFringeManifest(Options(dir));
    ADD_FAILURE() << "size mismatch accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("5.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("8x7 differs from 8x6"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "R" / "5.png") << "not an image";
  EXPECT_THROW(BuildFringeManifest(Options(dir)), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ramtk::vision
