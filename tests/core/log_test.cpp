#include "ramtk/core/log.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <vector>

#include "ramtk/core/error.h"

namespace ramtk {
namespace {

TEST(Log, SinkReceivesMessagesAtOrAboveThreshold) {
  std::vector<std::pair<LogLevel, std::string>> got;
  SetLogSink([&](LogLevel level, const std::string& m) { got.emplace_back(level, m); });
  SetLogThreshold(LogLevel::kWarning);
  RAMTK_LOG(kInfo) << "dropped";
  RAMTK_LOG(kWarning) << "condition number " << 1e8;
  Log(LogLevel::kError, "bad");
  SetLogSink({});
  SetLogThreshold(LogLevel::kInfo);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].first, LogLevel::kWarning);
  EXPECT_EQ(got[0].second, "condition number 1e+08");
  EXPECT_EQ(got[1].second, "bad");
}

// The file takes debug and above while the sink keeps its threshold; closing it restores the
// sink's threshold as the level below which messages are dropped.
TEST(Log, FileTakesDebugWhileTheSinkKeepsItsThreshold) {
  const std::string path = ::testing::TempDir() + "ramtk_log_test.log";
  std::remove(path.c_str());
  std::vector<std::string> sink;
  SetLogSink([&](LogLevel, const std::string& m) { sink.push_back(m); });
  SetLogThreshold(LogLevel::kWarning);
  SetLogFile(path);
  EXPECT_EQ(LogThreshold(), LogLevel::kDebug);
  RAMTK_LOG(kDebug) << "step " << 3;
  Log(LogLevel::kWarning, "rank deficient");
  LogToFile(LogLevel::kInfo, "file only");
  SetLogFile("");
  EXPECT_EQ(LogThreshold(), LogLevel::kWarning);
  Log(LogLevel::kError, "after close");
  SetLogSink({});
  SetLogThreshold(LogLevel::kInfo);
  EXPECT_EQ(sink, (std::vector<std::string>{"rank deficient", "after close"}));
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  const std::regex stamp(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z (debug|info|warning|error): .+$)");
  for (const auto& line : lines) EXPECT_TRUE(std::regex_match(line, stamp)) << line;
  EXPECT_NE(lines[0].find("debug: step 3"), std::string::npos);
  EXPECT_NE(lines[1].find("warning: rank deficient"), std::string::npos);
  EXPECT_NE(lines[2].find("info: file only"), std::string::npos);
  EXPECT_THROW(SetLogFile(::testing::TempDir() + "no_such_folder/x.log"), InputError);
}

}  // namespace
}  // namespace ramtk
