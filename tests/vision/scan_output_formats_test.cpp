// The scan's output table (scan_output_formats.h): the folder ScanOutputWriter writes holds
// exactly the table's files, docs/formats.md lists exactly its rows, and a format added through
// the table (a test-only writer registered here) is called and its file written.
#include "ramtk/vision/scan/scan_output_formats.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "ramtk/core/file_io.h"
#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {
namespace {

namespace fs = std::filesystem;

// A small result without a sphere: four points and a 3 x 2 depth map (NaN where no point).
ScanResult SmallResult() {
  ScanResult r;
  r.cloud.points_in_left = {{1.5f, -2.0f, 700.0f}, {2.5f, -2.0f, 701.0f}, {1.5f, -1.0f, 702.0f}, {2.5f, -1.0f, 703.0f}};
  r.cloud.sigma_mm = {0.01f, 0.02f, 0.03f, 0.04f};
  r.depth = cv::Mat(2, 3, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  r.depth.at<float>(0, 0) = 700.0f, r.depth.at<float>(0, 1) = 701.0f;
  r.depth.at<float>(1, 0) = 702.0f, r.depth.at<float>(1, 1) = 703.0f;
  r.summary.width = 3, r.summary.height = 2;
  r.summary.termination = Termination::kNoResult;
  r.summary.message = "no sphere found";
  r.summary.spheres.termination = Termination::kNoResult;
  r.summary.spheres.message = "no sphere found";
  r.summary.spheres.no_sphere_reason = "a test result";
  return r;
}

std::string FreshFolder(const std::string& name) {
  const fs::path dir = fs::path(RAMTK_TEST_OUTPUT_DIR) / "scan_output_formats" / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir.string();
}

std::set<std::string> FilesIn(const std::string& dir) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files.insert(e.path().filename().string());
  return files;
}

// The table's files: every row's, or without `report` the rows written without --report.
std::set<std::string> TableFiles(bool report) {
  std::set<std::string> files;
  for (const ScanOutputFormat& f : ScanOutputFormats())
    if (report || !f.report_only) files.insert(f.file);
  return files;
}

TEST(ScanOutputFormats, TheFolderHoldsExactlyTheTableFiles) {
  const ScanResult r = SmallResult();
  for (const bool report : {false, true}) {
    const std::string dir = FreshFolder(report ? "with_report" : "without_report");
    WriteScanOutputs(dir, r, false, report);
    EXPECT_EQ(FilesIn(dir), TableFiles(report)) << "report " << report;
  }
  // The files written without --report are the ones the command lists.
  std::set<std::string> listed;
  std::stringstream list(ScanOutputFileList(false));
  for (std::string f; std::getline(list, f, ',');) listed.insert(f.substr(f.find_first_not_of(' ')));
  EXPECT_EQ(listed, TableFiles(false));
}

TEST(ScanOutputFormats, EveryRowHasANameAFileAKindHelpAndAWriter) {
  std::set<std::string> names, files;
  for (const ScanOutputFormat& f : ScanOutputFormats()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_TRUE(files.insert(f.file).second) << f.file;
    EXPECT_FALSE(f.kind.empty()) << f.name;
    EXPECT_FALSE(f.help.empty()) << f.name;
    EXPECT_TRUE(static_cast<bool>(f.write)) << f.name;
  }
}

// docs/formats.md holds the table between its markers, as ScanOutputFormatsMarkdown writes it.
TEST(ScanOutputFormats, DocsTableListsExactlyTheTableRows) {
  const std::string doc = ReadTextFile(std::string(RAMTK_SOURCE_DIR) + "/docs/formats.md");
  const std::string begin = "<!-- scan-output-formats: begin (ScanOutputFormatsMarkdown) -->\n";
  const std::string end = "<!-- scan-output-formats: end -->";
  const std::size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()), ScanOutputFormatsMarkdown())
      << "docs/formats.md's scan output table should read:\n"
      << ScanOutputFormatsMarkdown();
}

// A row registered for the duration of a test.
struct RegisteredFormat {
  explicit RegisteredFormat(ScanOutputFormat f) : name(f.name) { RegisterScanOutputFormat(std::move(f)); }
  ~RegisteredFormat() { RemoveScanOutputFormat(name); }
  std::string name;
};

// docs/architecture.md, "A new output format": one row in the table is all a format needs.
TEST(ScanOutputFormats, AFormatAddedToTheTableIsWrittenIntoTheFolder) {
  int calls = 0;
  ScanOutputFormat points;
  points.name = "points_csv";
  points.file = "points.csv";
  points.kind = "CSV";
  points.help = "x, y, z of each point (mm, left-camera frame)";
  points.stage = ScanOutputStage::kResult;
  points.write = [&](const ScanOutputContext& c) {
    ++calls;
    std::ofstream out(c.PathOf("points.csv"));
    out << "x_mm,y_mm,z_mm\n";
    for (const Eigen::Vector3f& p : c.result->cloud.points_in_left)
      out << p.x() << "," << p.y() << "," << p.z() << "\n";
  };
  const ScanResult r = SmallResult();
  {
    const RegisteredFormat added(points);
    EXPECT_NE(ScanOutputFileList(false).find("points.csv"), std::string::npos);
    EXPECT_NE(ScanOutputFormatsMarkdown().find("| `points.csv` | CSV | always |"), std::string::npos);
    const std::string dir = FreshFolder("added");
    WriteScanOutputs(dir, r, false, false);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(FilesIn(dir), TableFiles(false));
    EXPECT_EQ(ReadTextFile(dir + "/points.csv"), "x_mm,y_mm,z_mm\n1.5,-2,700\n2.5,-2,701\n1.5,-1,702\n2.5,-1,703\n");
    EXPECT_THROW(RegisterScanOutputFormat(points), std::invalid_argument);  // the name is taken
  }
  // Removed again: the next folder is the built-in table's.
  const std::string dir = FreshFolder("removed");
  WriteScanOutputs(dir, r, false, false);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(FilesIn(dir).count("points.csv"), 0u);
}

// A row written with the cloud runs from ScanOutputWriter::WriteCloud, before Finish.
TEST(ScanOutputFormats, ACloudStageFormatIsWrittenWithTheCloud) {
  std::size_t points_seen = 0;
  ScanOutputFormat count;
  count.name = "point_count";
  count.file = "point_count.txt";
  count.kind = "text";
  count.help = "the number of points";
  count.stage = ScanOutputStage::kCloud;
  count.write = [&](const ScanOutputContext& c) {
    points_seen = c.cloud->size();
    WriteFileAtomically(c.PathOf("point_count.txt"), std::to_string(c.cloud->size()) + "\n");
  };
  const RegisteredFormat added(count);
  const ScanResult r = SmallResult();
  const std::string dir = FreshFolder("cloud_stage");
  ScanOutputWriter writer(dir, false, "test set");
  writer.WriteCloud(r.cloud, r.depth);
  EXPECT_EQ(points_seen, r.cloud.size());
  writer.Finish(r, false);
  EXPECT_EQ(ReadTextFile(dir + "/point_count.txt"), "4\n");
}

}  // namespace
}  // namespace ramtk::vision
