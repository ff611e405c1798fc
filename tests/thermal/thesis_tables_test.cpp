// The thesis's screening tables (datasets/thermal/, typed from §5.1): what they imply about λ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ramtk/core/csv.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/robot_model.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::thermal {
namespace {

const std::string kDir = std::string(RAMTK_DATASETS_DIR) + "/thermal/";

// λ printed to 2 decimals is k/N for an integer k: N is the number of monitored directions.
bool IsMultipleOf(double percent, int n) {
  const double k = percent * n / 100.0;
  return std::abs(k - std::round(k)) * 100.0 / n < 0.0051;
}

TEST(ThesisTables, LambdaCountsEightyEightEightyFiveAndSeventySevenDirections) {
  const CsvTable t51 = ReadCsv(kDir + "thesis_table_5_1.csv");
  const int lambda = t51.Column("lambda_percent");
  bool all_102 = true;
  for (std::size_t r = 0; r < t51.size(); ++r) {
    EXPECT_TRUE(IsMultipleOf(t51.Number(r, lambda), 88)) << t51.Number(r, lambda);
    all_102 &= IsMultipleOf(t51.Number(r, lambda), 102);
  }
  EXPECT_FALSE(all_102);  // not 34 points × 3 coordinates
  const CsvTable t52 = ReadCsv(kDir + "thesis_table_5_2.csv");
  const int directions[] = {88, 85, 77};
  for (std::size_t r = 0; r < t52.size(); ++r) {
    for (const char* col : {"before", "traditional", "screened"}) {
      EXPECT_TRUE(IsMultipleOf(t52.Number(r, t52.Column(col)), directions[r])) << "run " << r + 1 << " " << col;
    }
  }
}

// Table 5-1 against the procedure of Fig. 3-5, whose step (4) only tries removing elements of the
// steady set S of the row before. Two rows break it: a6 (card 17) is not in row 18's S and a4
// (card 9) is not in row 10's S — a thesis inconsistency (typo, or a fallback the text does not
// describe). The other 14 removals follow the procedure and the last 8 are the thesis's result.
TEST(ThesisTables, EliminationFollowsFigure3_5ExceptTwoRows) {
  const kinematics::RobotModel kr150 =
      kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
  const CsvTable t = ReadCsv(kDir + "thesis_table_5_1.csv");
  std::vector<int> current = kr150.FreeParams();
  ASSERT_EQ(current.size(), 24u);
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ';')) out.push_back(item);
    return out;
  };
  std::vector<std::string> previous_steady, outside_s;
  for (std::size_t r = 0; r < t.size(); ++r) {
    const std::string removed = t.Text(r, t.Column("removed"));
    if (r > 0) {
      if (std::find(previous_steady.begin(), previous_steady.end(), removed) == previous_steady.end()) {
        outside_s.push_back(removed + "@" + t.Text(r, t.Column("card")));
      }
      const int index = kinematics::ParamIndexFromName(removed);
      ASSERT_GE(index, 0) << removed;
      const auto it = std::find(current.begin(), current.end(), index);
      ASSERT_NE(it, current.end()) << removed << " removed twice";
      current.erase(it);
    }
    EXPECT_EQ(static_cast<int>(t.Integer(r, t.Column("card"))), static_cast<int>(current.size()));
    previous_steady = split(t.Text(r, t.Column("steady_set")));
  }
  EXPECT_EQ(outside_s, (std::vector<std::string>{"a6@17", "a4@9"}));
  EXPECT_EQ(ParamListToString(current), "d4,d6,a1,a2,a3,alpha3,alpha4,beta2");
}

}  // namespace
}  // namespace ramtk::thermal
