#include "ramtk/diagnose/engine/report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "ramtk/core/error.h"
#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/diagnose/fringe/fringe_hidden.h"
#include "ramtk/diagnose/laser/laser_hidden.h"
#include "ramtk/report/gnuplot.h"
#include "ramtk/tcf/simulator.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::diagnose {
namespace {

TEST(Catalogue, HoldsTheStableNamesOfDesignMd) {
  // DESIGN.md's names (wave 1 and wave 2): names may be added, never renamed or removed.
  for (const char* name :
       {"projector_nonlinearity", "phase_shift_error", "intensity_drift", "saturation", "defocus", "ambient_light",
        "lens_distortion_unmodelled", "camera_defocus", "signal_dependent_noise", "soft_knee_response",
        "joint_offset", "link_length_error", "thermal_length_drift", "thermal_angle_drift", "joint_compliance",
        "sensor_frame_drift", "tool_offset_change", "joint_cyclic_error", "backlash", "temperature_driven_drift",
        "geometric", "axis_misalignment", "beam_non_perpendicular", "beam_offset", "beam_width", "trigger_latency",
        "speed_variation", "sensor_plane_tilt", "tool_axis_rotation", "ambiguous", "not_observable"})
    EXPECT_TRUE(IsKnownCause(name)) << name;
  EXPECT_TRUE(IsKnownCause(kNoEffect));
  EXPECT_FALSE(IsKnownCause("gremlins"));
  std::set<std::string> names;
  for (const EffectInfo& e : EffectCatalogue()) {
    EXPECT_TRUE(names.insert(e.name).second) << "twice: " << e.name;
    EXPECT_GT(std::string(e.description).size(), 10u) << e.name;
  }
}

// docs/diagnose.md carries the catalogue table exactly as the tables generate it.
TEST(Catalogue, DocsTableListsExactlyTheTableRows) {
  std::ifstream in(std::string(RAMTK_DOCS_DIR) + "/diagnose.md");
  ASSERT_TRUE(in.good());
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string table = CatalogueMarkdown();
  EXPECT_NE(docs.find(table), std::string::npos) << "docs/diagnose.md should carry this table:\n" << table;
  // Every table row of the docs that names a cause is one of the catalogue's.
  size_t rows = 0;
  for (size_t at = docs.find("\n| `"); at != std::string::npos; at = docs.find("\n| `", at + 1)) {
    const size_t end = docs.find('`', at + 4);
    const std::string name = docs.substr(at + 4, end - at - 4);
    if (docs.compare(end + 1, 3, " | ") == 0 && IsKnownCause(name)) ++rows;
  }
  EXPECT_EQ(rows, EffectCatalogue().size());
}

// The simulators name their effects as the tables do: the fringe rows the hidden draws render are
// exactly the vision simulator's effects, the laser rows exactly the TCF simulator's.
TEST(Catalogue, SimulatorEffectsAreTheTablesRows) {
  const std::vector<std::string> table = vision::FringeEffects::Names();
  const std::set<std::string> simulator(table.begin(), table.end());
  EXPECT_EQ(simulator.size(), table.size());
  std::set<std::string> by_name;
  for (const auto& [name, magnitude] : vision::FringeEffects{}.ByName()) by_name.insert(name);
  EXPECT_EQ(by_name, simulator);
  const std::vector<std::string> drawn = DrawnFringeEffects();
  EXPECT_EQ(simulator, std::set<std::string>(drawn.begin(), drawn.end()));
  // Each row is settable by its name; an unknown name is refused listing every row.
  for (const std::string& name : table) {
    vision::FringeEffects e;
    e.Set(name, 0.5);
    EXPECT_EQ(e.ByName().at(name), 0.5) << name;
  }
  try {
    vision::FringeEffects{}.Set("no_such_effect", 1.0);
    ADD_FAILURE() << "an unknown effect was accepted";
  } catch (const InputError& error) {
    for (const std::string& name : table) EXPECT_NE(std::string(error.what()).find(name + " ("), std::string::npos) << name;
  }
  std::set<std::string> laser_rows;
  for (const EffectInfo& e : EffectsOf(DataKind::kLaser)) laser_rows.insert(e.name);
  const std::vector<std::string> device = tcf::DeviceEffects::Names();
  EXPECT_EQ(std::set<std::string>(device.begin(), device.end()), laser_rows);
  for (const std::string& name : DrawnLaserEffects()) EXPECT_TRUE(laser_rows.count(name)) << name;
}

// The help lines of each kind list its causes, one line each.
TEST(Catalogue, HelpListsEveryCauseOfTheKind) {
  for (DataKind kind : {DataKind::kFringe, DataKind::kRobot, DataKind::kLaser}) {
    const std::string help = CatalogueHelp(kind);
    EXPECT_EQ(static_cast<size_t>(std::count(help.begin(), help.end(), '\n')), EffectsOf(kind).size());
    for (const EffectInfo& e : EffectsOf(kind)) EXPECT_NE(help.find(std::string("  ") + e.name + " "), std::string::npos);
  }
}

TEST(Report, JsonCarriesCauseGainAndCandidates) {
  Diagnosis d;
  d.kind = DataKind::kLaser;
  d.unit = "mm";
  d.cause = "trigger_latency";
  d.parameters = {{"latency_s", 0.0021}};
  d.confidence = 0.97;
  d.rms_before = 0.2, d.rms_after = 0.05, d.noise_floor_rms = 0.04;
  d.excess_removed = ExcessRemoved(d.rms_before, d.rms_after, d.noise_floor_rms);
  CandidateFit c;
  c.effect = "trigger_latency";
  c.num_parameters = 1;
  d.candidates = {c};
  const nlohmann::json j = nlohmann::json::parse(DiagnosisJson(d));
  EXPECT_EQ(j["cause"], "trigger_latency");
  EXPECT_EQ(j["kind"], "laser");
  EXPECT_DOUBLE_EQ(j["parameters"]["latency_s"].get<double>(), 0.0021);
  EXPECT_NEAR(j["heldout"]["excess_removed"].get<double>(), (0.04 - 0.0025) / (0.04 - 0.0016), 1e-12);
  EXPECT_EQ(j["candidates"].size(), 1u);
  EXPECT_NE(DiagnosisMarkdown(d).find("trigger_latency"), std::string::npos);
}

TEST(Report, WritesJsonReportAndAReadablePlot) {
  const std::string dir = std::string(RAMTK_TEST_OUTPUT_DIR) + "/report";
  std::filesystem::remove_all(dir);
  Diagnosis d;
  report::Series s;
  for (int i = 0; i < 50; ++i) s.x.push_back(i), s.y.push_back(std::sin(i * 0.3));
  s.label = "residual";
  AddFigure(OnePanel("residual", "residual against time", "residual against time", "time (h)", "residual (mm)", {s},
                     0.5),
            dir, &d.pictures);
  ASSERT_EQ(d.pictures.size(), 1u);
  ASSERT_EQ(d.pictures[0].file, "residual.png");
  ASSERT_TRUE(d.pictures[0].figure.has_value());
  WriteDiagnosis(d, dir);
  EXPECT_TRUE(std::filesystem::exists(dir + "/diagnosis.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/report.md"));
  const cv::Mat img = cv::imread(dir + "/residual.png");
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, report::PngOptions().width);
  EXPECT_EQ(img.rows, report::PngOptions().panel_height);
  EXPECT_THROW(AddFigure(OnePanel("empty", "", "", "", "", {}), dir, &d.pictures), std::invalid_argument);
}

}  // namespace
}  // namespace ramtk::diagnose
