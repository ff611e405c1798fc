#include "ramtk/core/log.h"

#include <gtest/gtest.h>

#include <vector>

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

}  // namespace
}  // namespace ramtk
