// Laser log and programmed-motion files: round trips and errors that name the field.
#include "ramtk/tcf/device_io.h"

#include <gtest/gtest.h>

#include "ramtk/core/error.h"
#include "ramtk/tcf/simulator.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::tcf {
namespace {

TEST(DeviceIo, RoundTripGivesTheSameSolution) {
  TcfSimulationOptions o;
  o.seed = 5;
  const TcfSimulation sim = SimulateTcf(o);
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary direct = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  const auto events = ParseDeviceLog(FormatDeviceLog(sim.events), "log.csv");
  const auto motion = ProgrammedMotionFromJson(ProgrammedMotionToJson(sim.motion), "motion.json");
  const auto sensor = SensorFrameFromJson(SensorFrameToJson(sim.calibrated_sensor), "sensor.json");
  const TcfSummary read = SolveTcf(events, motion, sensor, opt);
  // The log is written with 1e-7 s resolution: at 180°/s and R = 12 mm that is 4e-6 mm of path.
  EXPECT_LT((read.solution.tcp_in_flange - direct.solution.tcp_in_flange).norm(), 1e-4);
}

TEST(DeviceIo, BadLogFieldsAreNamed) {
  try {
    ParseDeviceLog("time_s,beam,state\n0.1,z,blocked\n", "log.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().field, "beam");
  }
  try {
    ParseDeviceLog("time_s,beam,state\n0.2,x,blocked\n0.1,x,clear\n", "log.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().field, "time_s");
  }
}

TEST(DeviceIo, BadMotionFieldsAreNamed) {
  TcfSimulationOptions o;
  std::string json = ProgrammedMotionToJson(SimulateTcf(o).motion);
  const std::string key = "\"direction\": \"ccw\"";
  json.replace(json.find(key), key.size(), "\"direction\": \"up\"");
  try {
    ProgrammedMotionFromJson(json, "motion.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "circles[0].direction");
  }
  try {
    ProgrammedMotionFromJson("{\"tool_radius_mm\": 2.5}", "motion.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "circles");
  }
}

}  // namespace
}  // namespace ramtk::tcf
