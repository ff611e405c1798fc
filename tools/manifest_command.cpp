// ramtk manifest DIR --sequence SPEC [--left GLOB --right GLOB --calib FILE]: a checked fringe-set
// manifest from a capture folder (ramtk::vision BuildFringeManifest).

#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/vision/fringe/manifest_builder.h"

namespace ramtk::tools {
namespace {

struct ManifestCommandOptions {
  std::string folder;
  std::string sequence;
  std::string left, right;  // globs relative to the folder
  std::string calib;
  std::string projector;  // WxH
  std::string direction = "vertical";
  std::string out;  // default <folder>/manifest.json
};

int RunManifest(const ManifestCommandOptions& opt) {
  vision::ManifestBuildOptions o;
  o.folder = opt.folder;
  o.sequence = opt.sequence;
  if (!opt.left.empty()) o.camera_globs["left"] = opt.left;
  if (!opt.right.empty()) {
    if (opt.left.empty()) throw InputError({"", 0, "--right"}, "--right needs --left");
    o.camera_globs["right"] = opt.right;
  }
  o.calibration = opt.calib;
  int w = 0, h = 0;
  char tail = 0;
  if (std::sscanf(opt.projector.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w <= 0 || h <= 0)
    throw InputError({"", 0, "--projector"}, "expected WIDTHxHEIGHT in projector pixels, e.g. 1280x720, got '" +
                                                 opt.projector + "'");
  o.projector_width = w, o.projector_height = h;
  o.direction = opt.direction == "horizontal" ? vision::FringeDirection::kHorizontal : vision::FringeDirection::kVertical;
  o.output = !opt.out.empty() ? opt.out : (std::filesystem::path(opt.folder) / "manifest.json").string();
  vision::ManifestBuildSummary summary;
  const vision::FringeManifest m = vision::BuildFringeManifest(o, &summary);
  std::vector<std::string> inputs;  // the images and the calibration (InputFiles also names the manifest)
  for (const auto& [name, files] : m.cameras)
    for (const std::string& f : files) inputs.push_back(m.Resolve(f));
  if (!m.calibration.empty()) inputs.push_back(m.Resolve(m.calibration));
  CheckOutputAgainstInputs(o.output, inputs, "--out");
  vision::WriteFringeManifest(o.output, m);
  std::printf("%s\nwrote %s\n", summary.BriefReport().c_str(), o.output.c_str());
  return kExitOk;
}

}  // namespace

void RegisterManifestCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<ManifestCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "manifest", "Writes a checked fringe-set manifest from a capture folder: frame counts against the sequence, "
                  "every image readable, one image size");
  sub->add_option("folder", opt->folder, "Capture folder (the globs are relative to it)")->required();
  sub->add_option("--sequence", opt->sequence,
                  "Projected sequence, comma-separated blocks of the codec table (ramtk patterns --help): " +
                      vision::SequenceSpecForms() + "; e.g. ps:12:64,cgc:7")
      ->required();
  sub->add_option("--projector", opt->projector, "Projector resolution WIDTHxHEIGHT (pixels), e.g. 1280x720")
      ->required();
  sub->add_option("--left", opt->left,
                  "Glob of the (left) camera's frames, relative to the folder, natural order (1, 2, 10); default "
                  "L/* or left/*");
  sub->add_option("--right", opt->right, "Glob of the right camera's frames; default R/* or right/* beside L/left");
  sub->add_option("--calib", opt->calib, "Stereo calibration file, written relative to the manifest");
  sub->add_option("--direction", opt->direction, "Fringe direction")
      ->check(CLI::IsMember({"vertical", "horizontal"}))
      ->capture_default_str();
  sub->add_option("--out", opt->out, "Manifest to write (default <folder>/manifest.json)");
  sub->callback([opt, exit_code]() { *exit_code = RunManifest(*opt); });
}

}  // namespace ramtk::tools
