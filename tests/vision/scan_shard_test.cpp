// Shards of a scan batch (docs/cluster.md): every set in exactly one shard; merge refuses
// missing, duplicated and foreign rows.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "ramtk/core/error.h"
#include "ramtk/vision/scan/scan_batch.h"

namespace ramtk::vision {
namespace {

TEST(ScanShard, ShardsCoverEveryPositionExactlyOnce) {
  for (std::size_t n_sets : {0u, 1u, 7u, 12u, 1800u}) {
    for (int n : {1, 2, 3, 4, 7, 32}) {
      if (static_cast<std::size_t>(n) > n_sets) {
        EXPECT_THROW(ShardPositions(n_sets, {1, n}), InputError) << n << " shards of " << n_sets << " sets";
        continue;
      }
      std::multiset<std::size_t> seen;
      std::size_t largest = 0, smallest = n_sets;
      for (int k = 1; k <= n; ++k) {
        const auto p = ShardPositions(n_sets, {k, n});
        seen.insert(p.begin(), p.end());
        largest = std::max(largest, p.size());
        smallest = std::min(smallest, p.size());
      }
      ASSERT_EQ(seen.size(), n_sets);
      for (std::size_t i = 0; i < n_sets; ++i) EXPECT_EQ(seen.count(i), 1u);
      EXPECT_LE(largest - smallest, 1u);  // balanced within one set
    }
  }
  EXPECT_EQ(ShardPositions(10, {2, 4}), (std::vector<std::size_t>{1, 5, 9}));
}

TEST(ScanBatchList, PredictedCentresAreReadAndBadOnesNamedByLine) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(RAMTK_TEST_OUTPUT_DIR) / "batch_list_centres";
  fs::create_directories(dir);
  {
    std::ofstream(dir / "list.txt") << "# campaign\n"
                                       "a/manifest.json\n"
                                       "b/manifest.json  1.5,-2,700.25\r\n"
                                       "\n"
                                       "c d/manifest.json\n"
                                       "/abs/e/manifest.json\t-3,4,650\n";
  }
  const std::vector<ScanBatchEntry> e = ReadScanBatchEntries((dir / "list.txt").string());
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0].set, (dir / "a/manifest.json").string());
  EXPECT_FALSE(e[0].predicted_centre_in_left_mm);
  EXPECT_EQ(e[1].set, (dir / "b/manifest.json").string());
  ASSERT_TRUE(e[1].predicted_centre_in_left_mm);
  EXPECT_EQ(*e[1].predicted_centre_in_left_mm, Vec3(1.5, -2, 700.25));
  EXPECT_EQ(e[2].set, (dir / "c d/manifest.json").string());  // a space in the path, no centre
  EXPECT_FALSE(e[2].predicted_centre_in_left_mm);
  EXPECT_EQ(e[3].set, "/abs/e/manifest.json");
  EXPECT_EQ(*e[3].predicted_centre_in_left_mm, Vec3(-3, 4, 650));
  EXPECT_EQ(ReadScanBatchList((dir / "list.txt").string()).size(), 4u);  // paths only, for merge
  for (const char* bad : {"x/manifest.json 1,2", "x/manifest.json 1,2,nan", "x/manifest.json 1,2,3,4"}) {
    std::ofstream(dir / "bad.txt") << "# first\n" << bad << "\n";
    try {
      ReadScanBatchEntries((dir / "bad.txt").string());
      ADD_FAILURE() << bad;
    } catch (const InputError& ex) {
      EXPECT_NE(std::string(ex.what()).find("bad.txt:2"), std::string::npos) << ex.what();
    }
  }
}

TEST(ScanShard, ParsesKOverN) {
  const ScanShard s = ParseScanShard("3/8");
  EXPECT_EQ(s.index, 3);
  EXPECT_EQ(s.count, 8);
  for (const char* bad : {"0/4", "5/4", "3", "a/b", "2/", "/2", "2/4x", "-1/4", "1/4294967297", "4294967297/4294967297",
                          "1/+4", "1/ 4", "1/1000000000"}) {
    EXPECT_THROW(ParseScanShard(bad), InputError) << bad;
  }
  EXPECT_EQ(ShardResultsName({2, 4}), "results.shard-2-of-4.csv");
}

TEST(ScanShard, MergeOrdersRowsAndRefusesGapsAndDuplicates) {
  const std::filesystem::path d = std::filesystem::path(RAMTK_TEST_OUTPUT_DIR) / "shard_merge";
  std::filesystem::create_directories(d);
  const std::string header = "set,status,message";
  auto write = [&](const std::string& name, const std::string& body) {
    std::ofstream((d / name).string()) << header << "\n" << body;
    return (d / name).string();
  };
  const std::string a = write("a.csv", "s0,ok,\ns2,ok,\n");
  const std::string b = write("b.csv", "s1,error,\"bad, quoted\"\n");
  const std::vector<std::string> sets = {"s0", "s1", "s2"};
  EXPECT_EQ(MergeScanShards(sets, {a, b}, true), header + "\ns0,ok,\ns1,error,\"bad, quoted\"\ns2,ok,\n");
  // An error row is refused unless asked for, naming its file and line.
  try {
    MergeScanShards(sets, {a, b});
    ADD_FAILURE() << "an error row was merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.csv:2"), std::string::npos) << e.what();
  }
  // A row with a cell more or less than the header.
  const std::string short_row = write("short.csv", "s1,ok\n");
  try {
    MergeScanShards(sets, {a, short_row});
    ADD_FAILURE() << "a short row was merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("short.csv:2"), std::string::npos) << e.what();
  }
  // A set listed twice needs two rows.
  EXPECT_THROW(MergeScanShards({"s0", "s1", "s2", "s2"}, {a, b}, true), InputError);
  // A shard missing, run twice, or a row of another batch.
  EXPECT_THROW(MergeScanShards(sets, {a}, true), InputError);
  EXPECT_THROW(MergeScanShards(sets, {a, b, b}, true), InputError);
  EXPECT_THROW(MergeScanShards({"s0", "s2"}, {a, b}, true), InputError);
  std::ofstream((d / "c.csv").string()) << "set,status\ns1,ok\n";
  EXPECT_THROW(MergeScanShards(sets, {a, (d / "c.csv").string()}, true), InputError);  // header differs
}

// --resume: a set folder's row.csv is kept only for the same set, the same settings and a
// finished status, and is written back into the results as it was.
TEST(ScanBatchResume, AFinishedRowIsKeptOnlyForTheSameSetAndSettings) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(RAMTK_TEST_OUTPUT_DIR) / "batch_resume" / "000_a";
  fs::remove_all(dir.parent_path());
  fs::create_directories(dir);
  const std::string header =
      "set,status,points,x_mm,y_mm,z_mm,radius_mm,sigma_x_mm,sigma_y_mm,sigma_z_mm,rms_mm,num_points,num_outliers,"
      "seconds,out_dir,message";
  const std::string cells = "/d/a/manifest.json,ok,100,1.5,-2,700,19.05,0.003,0.004,0.012,0.03,90,2,0.25,";
  auto write = [&](const std::string& status, const std::string& settings) {
    std::ofstream(dir / "row.csv") << header << ",settings\n"
                                   << "/d/a/manifest.json," << status << cells.substr(cells.find(",ok,") + 3)
                                   << dir.string() << ",," << settings << "\n";
  };
  write("ok", "radius=19.05");
  const auto kept = ReadFinishedSetRow(dir.string(), "/d/a/manifest.json", "radius=19.05");
  ASSERT_TRUE(kept);
  EXPECT_TRUE(kept->has_sphere);
  EXPECT_EQ(kept->sphere.centre_mm, Vec3(1.5, -2, 700));
  EXPECT_NEAR(kept->sphere.CentreSigma().z(), 0.012, 1e-15);
  EXPECT_EQ(ScanBatchCsv({*kept}), header + "\n" + cells + dir.string() + ",\n");
  EXPECT_FALSE(ReadFinishedSetRow(dir.string(), "/d/a/manifest.json", "radius=19"));
  EXPECT_FALSE(ReadFinishedSetRow(dir.string(), "/d/b/manifest.json", "radius=19.05"));
  write("error", "radius=19.05");
  EXPECT_FALSE(ReadFinishedSetRow(dir.string(), "/d/a/manifest.json", "radius=19.05"));
  fs::remove(dir / "row.csv");
  EXPECT_FALSE(ReadFinishedSetRow(dir.string(), "/d/a/manifest.json", "radius=19.05"));
}

// The batch totals: rows counted by status, the rate from the wall time, the peak memory read
// from the process (at least the memory this test holds).
TEST(ScanBatchSummary, CountsRowsAndGivesTheRateAndPeakMemory) {
  std::vector<ScanBatchRow> rows(7);
  for (auto& r : rows) r.status = "ok";
  rows[1].status = "no sphere found";
  rows[4].status = "error";
  rows[6].status = "cancelled";
  std::vector<char> held(64 << 20, 1);  // 64 MiB touched
  const ScanBatchSummary s = SummariseScanBatch(rows, 2.0);
  EXPECT_EQ(s.sets, 7u);
  EXPECT_EQ(s.ok, 4u);
  EXPECT_EQ(s.no_sphere, 1u);
  EXPECT_EQ(s.errors, 1u);
  EXPECT_EQ(s.cancelled, 1u);
  EXPECT_DOUBLE_EQ(s.sets_per_second, 3.5);
  EXPECT_GE(s.peak_memory_mb, 64.0 + held[12345] - 1);
  EXPECT_EQ(s.BriefReport().rfind("scanned 7 sets: 4 ok, 1 without a sphere, 1 with errors, 1 cancelled in 2.00 s "
                                  "(3.50 sets/s), peak memory ",
                                  0),
            0u)
      << s.BriefReport();
  EXPECT_EQ(SummariseScanBatch({}, 0.0).sets_per_second, 0.0);
}

}  // namespace
}  // namespace ramtk::vision
