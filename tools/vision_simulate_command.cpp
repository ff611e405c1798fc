// ramtk simulate fringe: render a stereo fringe image set with its calibration and ground truth.
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/units.h"
#include "ramtk/vision/fringe/sequence_spec.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::tools {
namespace {

struct SimulateFringeOptions {
  std::string preset = "small";        // thesis | small
  std::string out_dir;                 // output folder
  std::uint64_t seed = 1;              // random seed
  std::vector<std::string> effects;    // name=magnitude
  int bits = 8;                        // camera bit depth
  std::string frame_format = "png";    // png or bmp
  int supersampling = 4;               // n×n rays per pixel
  double fill_factor = std::numeric_limits<double>::quiet_NaN();  // pixel box aperture, px (NaN: keep)
  double psf_sigma = std::numeric_limits<double>::quiet_NaN();    // lens PSF σ, px (NaN: keep)
  bool monocular = false;              // also write the left camera as a camera–projector set
  std::string ball;                    // x,y,z of the ball centre in the left-camera frame, mm
  double radius = 0.0;                 // ball radius, mm (0 = preset)
  std::vector<std::string> spheres;    // extra spheres x,y,z,r (mm), e.g. the second ball of a ball bar
  bool no_backdrop = false;            // remove the backdrop plane
  std::string direction = "vertical";  // fringe direction
  std::string calibration;             // cameras from a stereo calibration file instead of the preset
  std::string sequence;                // pattern sequence spec ("" = the preset's)
  double phase_at_origin_deg =
      std::numeric_limits<double>::quiet_NaN();  // phase at projector pixel 0 of every phase block (NaN: keep)
  bool no_noise = false;                         // noiseless images
  bool force = false;                            // replace an existing output folder
  bool quiet = false;                            // no progress on stderr
};

int RunSimulateFringe(const SimulateFringeOptions& opt, Provenance provenance) {
  Vec3 ball(0.0, 0.0, 700.0);
  if (!opt.ball.empty()) {
    const std::vector<double> b = ParseDoubleList(opt.ball, {"", 0, "--ball"}, 3);
    ball = Vec3(b[0], b[1], b[2]);
  }
  vision::FringeSimulationConfig config =
      opt.calibration.empty() ? vision::MakeFringePreset(opt.preset, ball)
                              : vision::MakeFringeConfigForCalibration(camera::ReadStereoCalibration(opt.calibration));
  config.seed = opt.seed;
  if (!opt.sequence.empty()) config.sequence = vision::ParseSequenceSpec(opt.sequence, {"", 0, "--sequence"});
  if (std::isfinite(opt.phase_at_origin_deg)) {
    if (!(std::abs(opt.phase_at_origin_deg) <= 360.0))
      throw InputError({"", 0, "--phase-at-origin"}, "must be within [-360, 360] degrees");
    for (auto& b : config.sequence) b.phase_at_origin_rad = DegToRad(opt.phase_at_origin_deg);
  }
  config.sensor.bits = opt.bits;
  config.frame_format = opt.frame_format;
  config.sensor.noise = !opt.no_noise;
  config.supersampling = opt.supersampling;
  if (std::isfinite(opt.fill_factor) || std::isfinite(opt.psf_sigma)) {
    for (camera::CameraIntrinsics* cam : {&config.cameras.left, &config.cameras.right}) {
      camera::SamplingKernel k = cam->sampling_kernel.value_or(camera::SamplingKernel{});
      if (std::isfinite(opt.fill_factor)) k.fill_factor = opt.fill_factor;
      if (std::isfinite(opt.psf_sigma)) k.psf_sigma_px = opt.psf_sigma;
      cam->sampling_kernel = k;
    }
  }
  // The written calibration states the kernel the render samples (RenderedKernel).
  config = vision::StateRenderedKernel(config);
  config.write_monocular = opt.monocular;
  for (const std::string& e : opt.effects) {
    const auto eq = e.find('=');
    if (eq == std::string::npos) throw InputError({"", 0, "--effect"}, "expected name=magnitude, got '" + e + "'");
    const std::string name = e.substr(0, eq);
    config.effects.Set(name, ParseDouble(e.substr(eq + 1), {"", 0, "--effect " + name}));
  }
  if (!opt.ball.empty()) config.scene.spheres.at(0).centre_in_left = ball;
  if (opt.radius != 0.0) config.scene.spheres.at(0).radius = opt.radius;
  for (std::size_t i = 0; i < opt.spheres.size(); ++i) {
    const std::vector<double> s = ParseDoubleList(opt.spheres[i], {"", 0, "--sphere"}, 4);
    if (!(s[3] > 0.0)) throw InputError({"", 0, "--sphere"}, "radius must be positive");
    config.scene.spheres.push_back({"sphere" + std::to_string(i + 2), Vec3(s[0], s[1], s[2]), s[3], 0.8});
  }
  if (opt.no_backdrop) config.scene.planes.clear();
  if (opt.direction == "horizontal") {
    config.direction = vision::FringeDirection::kHorizontal;
  } else if (opt.direction != "vertical") {
    throw InputError({"", 0, "--direction"}, "expected vertical or horizontal, got '" + opt.direction + "'");
  }
  ProgressCallback progress;
  if (!opt.quiet) {
    progress = ProgressPrinter("rows");
  }
  AddProvenanceFile(&provenance, opt.calibration);
  const vision::FringeSimulationSummary summary =
      vision::SimulateFringeSet(config, opt.out_dir, opt.force, progress, &provenance);
  std::cout << summary.BriefReport() << '\n';
  return kExitOk;
}

}  // namespace

void RegisterSimulateFringeCommand(CLI::App& app, int* exit_code) {
  CLI::App* simulate = SimulateCommand(app);
  auto opt = std::make_shared<SimulateFringeOptions>();
  CLI::App* sub = simulate->add_subcommand(
      "fringe", "Render a stereo fringe-projection image set, its calibration and ground truth");
  sub->add_option("--preset", opt->preset, "Rig and scene: thesis (3312x2488) or small (640x512 around the ball)")
      ->capture_default_str();
  sub->add_option("--out", opt->out_dir, "Output folder (must not exist, or be empty, unless --force)")->required();
  sub->add_option("--seed", opt->seed, "Random seed (recorded in the output)")->capture_default_str();
  sub->add_option("--effect", opt->effects, "Effect name=magnitude, repeatable: " + vision::FringeEffects::Help());
  sub->add_option("--bits", opt->bits, "Camera bit depth: 8, 10, 12 or 16")->capture_default_str();
  sub->add_option("--frame-format", opt->frame_format,
                  "Frame files: png, or bmp (uncompressed, 8-bit only: what many cameras write; `scan --roi` then "
                  "reads only the rows it needs)")
      ->capture_default_str();
  sub->add_option("--supersampling", opt->supersampling,
                  "n: n x n rays per camera pixel, through the sampling kernel (without --fill-factor or "
                  "--psf-sigma: the box pixel, fill factor 1; n = 1 samples a point, fill factor 0)")
      ->capture_default_str();
  sub->add_option("--fill-factor", opt->fill_factor,
                  "Pixel fill factor in [0, 1]: the width of the square box aperture each pixel integrates over, px "
                  "(default 1, or the --calib file's sampling_kernel; stated in the written calibration)");
  sub->add_option("--psf-sigma", opt->psf_sigma,
                  "Lens PSF: sigma of an isotropic Gaussian applied to the irradiance before the pixel's box, px "
                  "(default 0, or the --calib file's sampling_kernel; stated in the written calibration)");
  sub->add_flag("--monocular", opt->monocular,
                "Also write monocular.json and projector_calibration.yml: the left camera against the projector "
                "(a camera–projector set for `ramtk scan`)");
  sub->add_option(
      "--ball", opt->ball,
      "Ball centre x,y,z in the left-camera frame, mm (default 0,0,700; the small preset's windows follow it)");
  sub->add_option("--radius", opt->radius, "Ball radius, mm (default 19.05)");
  sub->add_option("--calib", opt->calibration,
                  "Take both cameras from this stereo calibration (e.g. caliInfo.yml); the ball goes where "
                  "the optical axes meet");
  sub->add_option("--sequence", opt->sequence,
                  "Pattern sequence, comma-separated blocks of the codec table (ramtk patterns --help): " +
                      vision::SequenceSpecForms() +
                      "; e.g. ps:12:64,cgc:7 (the default, SLMaster's), ps:4:16,gc:4 or "
                      "het:4:70/64/59");
  sub->add_option("--phase-at-origin", opt->phase_at_origin_deg,
                  "Phase at projector pixel 0 of every phase-shift block, degrees (default: the sequence's, -180)");
  sub->add_option("--sphere", opt->spheres, "Extra sphere x,y,z,r in mm (left-camera frame), repeatable");
  sub->add_flag("--no-backdrop", opt->no_backdrop, "Remove the backdrop plane");
  sub->add_option("--direction", opt->direction, "Fringe direction: vertical (codes projector x) or horizontal")
      ->capture_default_str();
  sub->add_flag("--no-noise", opt->no_noise, "Render without shot and read noise");
  sub->add_flag("--force", opt->force, "Replace an existing output folder");
  sub->add_flag("-q,--quiet", opt->quiet, "No progress on stderr");
  sub->callback([opt, exit_code, sub]() { *exit_code = RunSimulateFringe(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
