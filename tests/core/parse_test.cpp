#include "ramtk/core/parse.h"

#include <gtest/gtest.h>

namespace ramtk {
namespace {

TEST(Parse, Numbers) {
  EXPECT_EQ(ParseDouble(" -2.5 ", {}), -2.5);
  EXPECT_EQ(ParseDouble("1e3", {}), 1000.0);
  EXPECT_THROW(ParseDouble("", {}), InputError);
  EXPECT_THROW(ParseDouble("1.5mm", {}), InputError);
  EXPECT_THROW(ParseDouble("nan", {}), InputError);
  EXPECT_THROW(ParseDouble("1e999", {}), InputError);
}

TEST(Parse, ListNamesTheFieldAndIndex) {
  EXPECT_EQ(ParseDoubleList("1,2,3", {}, 3), (std::vector<double>{1, 2, 3}));
  try {
    ParseDoubleList("1,x,3", {"", 0, "--joints"}, 3);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "field '--joints[1]': expected a number, got 'x'");
  }
  EXPECT_THROW(ParseDoubleList("1,2", {"", 0, "--joints"}, 3), InputError);
  EXPECT_THROW(ParseDoubleList("1,2,", {"", 0, "--joints"}, 0), InputError);
}

TEST(Parse, LocationFormatting) {
  EXPECT_EQ(FormatLocation({"robot.yaml", 12, "joints[2].alpha"}), "robot.yaml:12: field 'joints[2].alpha'");
  EXPECT_EQ(FormatLocation({"robot.yaml", 0, ""}), "robot.yaml");
  const InputError e({"a.csv", 3, "x"}, "not a number");
  EXPECT_EQ(std::string(e.what()), "a.csv:3: field 'x': not a number");
}

}  // namespace
}  // namespace ramtk

namespace ramtk {
namespace {

// Half a unit of the last printed digit, read from the text alone.
TEST(Parse, PrintedRoundingBound) {
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("0.707107"), 5e-7);
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("-0.5"), 0.05);
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("12"), 0.5);
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("1.5e-3"), 5e-5);
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("7.07107E-01"), 5e-7);
  EXPECT_DOUBLE_EQ(PrintedRoundingBound("3e2"), 50.0);
}

}  // namespace
}  // namespace ramtk
