#pragma once
// Pieces of the campaign twin shared by its source files.
#include <string>

#include "ramtk/campaign/campaign.h"
#include "ramtk/thermal/simulator.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::campaign::internal {

struct CampaignFiles {
  std::string out_dir;
  thermal::ThermalSimOptions options;
  thermal::ThermalSimResult sim;
  bool cancelled = false;  // the progress callback asked to stop; the files are incomplete
};

std::string SetName(int cycle, int pose);  // "c003_p07"
// The "small" preset around the ball with its windows scaled by `scale`.
vision::FringeSimulationConfig CampaignFringeConfig(const Vec3& ball_in_left, double scale, int supersampling,
                                                    std::uint64_t seed);
// Simulates and writes the campaign's files; *render_s gets the rendering wall time. Stops
// rendering (cancelled = true) once the progress callback returns false.
CampaignFiles SimulateCampaignFiles(const kinematics::RobotModel& model, const CampaignOptions& options,
                                    const std::string& out_dir, double* render_s);

}  // namespace ramtk::campaign::internal
