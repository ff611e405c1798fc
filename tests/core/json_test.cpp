// The one pose encoding and the checked JSON getters: a pose written and read back, the three
// accepted forms of the same pose (built independently from a rotation about a known axis), and
// errors that name the file and the field.
#include "ramtk/core/json.h"

#include <gtest/gtest.h>

#include "error_message.h"
#include "ramtk/core/units.h"

namespace ramtk {
namespace {

Isometry3 SomePose() {
  Isometry3 t = Isometry3::Identity();
  t.linear() = Eigen::AngleAxisd(DegToRad(37.0), Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  t.translation() = Vec3(2037.2109, -1761.8217, 343.7652);
  return t;
}

using testing::Message;

TEST(Json, PoseRoundTripsThroughItsText) {
  const Isometry3 t = SomePose();
  const nlohmann::json j = ParseJsonText(PoseToJson(t).dump(), "pose.json");
  const Isometry3 back = JsonPose(j, "pose.json", "pose");
  // From position_mm + abc_deg (17 significant digits): rounding of the angles only.
  EXPECT_LT((back.matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // The matrix written beside them is the pose itself.
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(j["matrix"][r][c].get<double>(), t.matrix()(r, c));
}

TEST(Json, TheThreeFormsOfOnePoseAgree) {
  const Isometry3 t = SomePose();
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r)
    rows.push_back({t.linear()(r, 0), t.linear()(r, 1), t.linear()(r, 2), t.translation()(r)});
  const KukaAbc abc = KukaAbcFromRotation(t.linear());
  const nlohmann::json abc_form = {{"position_mm", {t.translation().x(), t.translation().y(), t.translation().z()}},
                                   {"abc_deg", {RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c)}}};
  const nlohmann::json matrix_form = {{"matrix", rows}};
  for (const nlohmann::json& form : {nlohmann::json(rows), matrix_form, abc_form}) {
    EXPECT_LT((JsonPose(form, "p.json", "pose").matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12) << form.dump();
  }
  // position_mm + abc_deg win over a stale matrix beside them (the documented reading order).
  nlohmann::json both = abc_form;
  both["matrix"] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  EXPECT_LT((JsonPose(both, "p.json", "pose").matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

// A key given twice in one object is refused at any depth; the same key in two objects is fine.
TEST(Json, AKeyTwiceInOneObjectIsRefused) {
  EXPECT_EQ(Message([] {
              ParseJsonText(R"({"a": 1, "b": 2, "a": 3})", "x.json");
            }).rfind("x.json: field 'a': duplicate key", 0),
            0u);
  EXPECT_EQ(Message([] {
              ParseJsonText(R"({"s": [{"r": 1}, {"r": 2, "q": 0, "r": 5}]})", "x.json");
            }).rfind("x.json: field 'r': duplicate key", 0),
            0u);
  const nlohmann::json ok =
      ParseJsonText(R"({"r": 1, "s": {"r": 2, "t": {"r": 3}}, "u": [{"r": 4}, {"r": 5}]})", "x.json");
  EXPECT_EQ(ok["s"]["t"]["r"], 3);
  EXPECT_EQ(ok["u"][1]["r"], 5);
}

TEST(Json, ErrorsNameTheFileAndTheField) {
  EXPECT_EQ(Message([] { ParseJsonText("{\"a\": 1e999}", "x.json"); }).rfind("x.json: not valid JSON", 0), 0u);
  const nlohmann::json j = nlohmann::json::parse(R"({"setup": {"pose": [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0]]},
                                                      "n": "seven", "v": [1, 2]})");
  EXPECT_EQ(Message([&] { JsonNumberAt(j, "n", "x.json"); }), "x.json: field 'n': expected a number, got \"seven\"");
  EXPECT_EQ(Message([&] { JsonVec3At(j, "v", "x.json"); }), "x.json: field 'v': expected an array of 3 numbers");
  EXPECT_EQ(Message([&] { JsonRequire(j, "missing", "x.json", "setup."); }),
            "x.json: field 'setup.missing': missing key");
  EXPECT_NE(Message([&] {
              JsonPoseAt(j.at("setup"), "pose", "x.json", "setup.");
            }).find("x.json: field 'setup.pose': rotation part is not orthonormal"),
            std::string::npos);
  EXPECT_EQ(Message([&] { JsonInt(nlohmann::json(2.5), "x.json", "k"); }),
            "x.json: field 'k': expected an integer, got 2.5");
}

}  // namespace
}  // namespace ramtk
