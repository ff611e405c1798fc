// The progress display: a line redrawn in place on a terminal, plain throttled lines elsewhere.
#include "progress_printer.h"

#include <gtest/gtest.h>

namespace ramtk::tools {
namespace {

TEST(ProgressPrinter, TerminalRedrawsOneLineWithRateAndTimeLeft) {
  const std::string line = ProgressLine({"scan", 5, 20}, "sets", true, 10.0, 0.0);
  EXPECT_EQ(line.front(), '\r');
  EXPECT_NE(line.find("5/20 sets (25%)"), std::string::npos) << line;
  EXPECT_NE(line.find("0.5 sets/s"), std::string::npos) << line;
  EXPECT_NE(line.find("30 s left"), std::string::npos) << line;  // 15 sets at 0.5 per s
  EXPECT_EQ(line.back(), 'K');                                    // no newline until the last
  EXPECT_EQ(ProgressLine({"scan", 20, 20}, "sets", true, 40.0, 0.0).back(), '\n');
}

TEST(ProgressPrinter, PipesGetPlainLinesAtMostEveryTenSeconds) {
  const std::string first = ProgressLine({"scan", 0, 20}, "sets", false, 0.0, 1e9);
  EXPECT_EQ(first.find('\r'), std::string::npos);
  EXPECT_EQ(first.back(), '\n');
  EXPECT_TRUE(ProgressLine({"scan", 3, 20}, "sets", false, 4.0, 4.0).empty());
  EXPECT_FALSE(ProgressLine({"scan", 9, 20}, "sets", false, 12.0, 12.0).empty());
  EXPECT_FALSE(ProgressLine({"scan", 20, 20}, "sets", false, 13.0, 1.0).empty());  // the last always
}

}  // namespace
}  // namespace ramtk::tools
