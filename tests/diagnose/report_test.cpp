#include "ramtk/diagnose/engine/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/report/gnuplot.h"

namespace ramtk::diagnose {
namespace {

TEST(Catalogue, HoldsTheStableNamesOfDesignMd) {
  // DESIGN.md: 7 + 7 + 7 names in wave 1, then fringe +3 and robot +3 (wave 2).
  EXPECT_EQ(EffectsOf(DataKind::kFringe).size(), 10u);
  EXPECT_EQ(EffectsOf(DataKind::kRobot).size(), 12u);
  EXPECT_EQ(EffectsOf(DataKind::kLaser).size(), 7u);
  EXPECT_TRUE(IsKnownCause("thermal_angle_drift"));
  for (const char* wave2 : {"camera_defocus", "signal_dependent_noise", "soft_knee_response", "joint_cyclic_error",
                            "backlash", "temperature_driven_drift", "ambiguous", "not_observable"})
    EXPECT_TRUE(IsKnownCause(wave2)) << wave2;
  EXPECT_TRUE(IsKnownCause(kNoEffect));
  EXPECT_FALSE(IsKnownCause("gremlins"));
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
