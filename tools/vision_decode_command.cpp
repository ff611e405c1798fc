// ramtk decode: absolute projector coordinate, modulation, mask and phase noise from a fringe set.
#include <iostream>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::tools {
namespace {

struct DecodeCommandOptions {
  std::string manifest;          // fringe image set manifest (JSON)
  std::string camera = "all";    // camera name or "all"
  std::string out;               // output folder
  double min_modulation = 0.02;  // B threshold, fraction of full scale
  double sigma_intensity = 0;    // DN; 0 = estimate
  std::string modulation_rule = "sigma";  // weak-fringe rejection: sigma or fixed (DecodeOptions)
  bool no_nonlinearity = false;  // skip the gamma ripple correction
  int phase_filter = 0;          // coordinate filter radius (px), 0 = off
  std::string format = "tiff";   // float image format: tiff or exr
  bool force = false;            // replace an existing output folder
};

int RunDecode(const DecodeCommandOptions& opt, Provenance provenance) {
  using namespace vision;
  if (!(opt.min_modulation >= 0 && opt.min_modulation <= 1))
    throw InputError({"", 0, "--min-modulation"}, "expected a fraction of full scale in [0, 1]");
  if (opt.format != "tiff" && opt.format != "exr")
    throw InputError({"", 0, "--format"}, "expected tiff or exr, got '" + opt.format + "'");
  if (!(opt.sigma_intensity >= 0)) throw InputError({"", 0, "--sigma-intensity"}, "expected a noise level >= 0 DN");
  DecodeOptions options;
  options.min_modulation_fraction = opt.min_modulation;
  options.modulation_rule = opt.modulation_rule == "fixed" ? ModulationRule::kFixed : ModulationRule::kSigma;
  options.intensity_sigma_dn = opt.sigma_intensity;
  options.correct_nonlinearity = !opt.no_nonlinearity;
  options.coordinate_filter.radius_px = opt.phase_filter;
  ThrowIfInvalid(options.Validate(), "DecodeOptions");
  const FringeManifest m = ReadFringeManifest(opt.manifest);
  CheckOutputAgainstInputs(opt.out, m.InputFiles(), "--out");
  std::vector<std::string> cameras;
  if (opt.camera == "all") {
    for (const auto& [name, files] : m.cameras) cameras.push_back(name);
  } else {
    cameras.push_back(opt.camera);
  }
  // Decode everything first: bad input anywhere leaves no output at all.
  std::vector<DecodedCamera> decoded;
  for (const std::string& c : cameras) decoded.push_back(DecodeCamera(m, c, options));
  // All cameras into one staged folder, moved into place when complete.
  StagedFolder staged(opt.out, opt.force, "--out");
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    WriteDecodedCamera(staged.path().string(), cameras[i], decoded[i], opt.format);
  }
  AddProvenanceFile(&provenance, opt.manifest);
  for (const std::string& f : m.InputFiles()) AddProvenanceFile(&provenance, f);
  WriteFolderProvenance(staged.path().string(), provenance);
  staged.Commit();
  for (const DecodedCamera& d : decoded) std::cout << d.summary.BriefReport() << "\n";
  std::cout << "wrote " << opt.out << "\n";
  return kExitOk;
}

}  // namespace

void RegisterDecodeCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<DecodeCommandOptions>();
  CLI::App* sub =
      app.add_subcommand("decode", "Decode a fringe image set into projector coordinates (TIFF + PNG previews)");
  sub->add_option("manifest", opt->manifest, "Fringe image set manifest (JSON)")->required();
  sub->add_option("--camera", opt->camera, "Camera name in the manifest, or all")->capture_default_str();
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--min-modulation", opt->min_modulation,
                  "Fixed rule: modulation threshold, fraction of full scale; sigma rule: the pixels the noise is "
                  "measured on")
      ->capture_default_str();
  sub->add_option("--modulation-rule", opt->modulation_rule,
                  "Weak-fringe pixels: sigma (rejected from their own phase noise) or fixed (--min-modulation)")
      ->check(CLI::IsMember({"sigma", "fixed"}))
      ->capture_default_str();
  sub->add_option("--sigma-intensity", opt->sigma_intensity, "Intensity noise in DN (0: estimate from the fit)")
      ->capture_default_str();
  sub->add_option("--format", opt->format, "Float image format: tiff or exr")->capture_default_str();
  sub->add_flag("--no-nonlinearity", opt->no_nonlinearity, "Do not correct the projector nonlinearity");
  sub->add_option("--phase-filter", opt->phase_filter,
                  "Smooth the coordinate map with a quadratic fit over a (2R+1)^2 window, R px (0 = off, at most 6); "
                  "carried into the sigma maps")
      ->check(CLI::Range(0, 6));
  sub->add_flag("--force", opt->force, "Replace an existing non-empty output folder (once the new one is complete)");
  sub->callback([opt, exit_code, sub]() { *exit_code = RunDecode(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
