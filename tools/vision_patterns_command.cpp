// ramtk patterns: writes a fringe pattern sequence (8/16-bit PNG) and its manifest.
#include <filesystem>
#include <iostream>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/parse.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/fringe/patterns.h"

namespace ramtk::tools {
namespace {

struct PatternsCommandOptions {
  std::string scheme = "complementary_gray_code";  // phase_shift | gray_code | complementary_gray_code | an absolute codec
  int width = 1280;                                // projector width, px
  int height = 720;                                // projector height, px
  std::string direction = "vertical";              // vertical | horizontal fringes
  int steps = 12;                                  // phase steps (per frequency)
  double cycles = 0;                               // periods across the projector (phase_shift / Gray code)
  double period = 0;                               // or the period in projector px
  std::string heterodyne = "70,64,59";             // heterodyne cycles, finest first
  double phase_at_origin_deg = -180;               // phase at projector pixel 0
  int bits = 8;                                    // PNG bit depth
  std::string out;                                 // output folder
  bool force = false;                              // replace an existing output folder
};

// The absolute codecs of the codec table, "a | b".
std::string AbsoluteCodecNames() {
  std::string names;
  for (const vision::PatternCodec* c : vision::PatternCodecs())
    if (c->role == vision::CodecRole::kAbsolute) names += (names.empty() ? "" : " | ") + c->name;
  return names;
}

// A block of an absolute codec, its parameters from the options: --steps, --heterodyne-cycles (a
// list) or --cycles (one value), --phase-at-origin.
vision::SequenceBlock AbsoluteBlock(const vision::PatternCodec& codec, const PatternsCommandOptions& opt,
                                    double phase0) {
  vision::SequenceBlock b;
  b.type = codec.type;
  if (codec.type == vision::BlockType::kRegistered) b.codec = codec.name;
  for (const vision::CodecParameter& p : codec.parameters) {
    if (p.field == vision::CodecField::kSteps) b.steps = opt.steps;
    if (p.field == vision::CodecField::kPhaseAtOrigin) b.phase_at_origin_rad = phase0;
    if (p.field == vision::CodecField::kCycles)
      b.cycles = p.max_count > 1 ? ParseDoubleList(opt.heterodyne, {"", 0, "--heterodyne-cycles"})
                                 : std::vector<double>{opt.cycles};
  }
  return b;
}

int RunPatterns(const PatternsCommandOptions& opt, const Provenance& provenance) {
  using namespace vision;
  FringeManifest m;
  m.projector_width = opt.width;
  m.projector_height = opt.height;
  if (opt.width <= 0 || opt.height <= 0) throw InputError({"", 0, "--width/--height"}, "must be positive");
  if (opt.direction == "vertical") {
    m.direction = FringeDirection::kVertical;
  } else if (opt.direction == "horizontal") {
    m.direction = FringeDirection::kHorizontal;
  } else {
    throw InputError({"", 0, "--direction"}, "expected vertical or horizontal, got '" + opt.direction + "'");
  }
  const double phase0 = opt.phase_at_origin_deg * 3.14159265358979323846 / 180.0;
  if (const PatternCodec* codec = FindPatternCodec(opt.scheme); codec && codec->role == CodecRole::kAbsolute) {
    m.sequence.push_back(AbsoluteBlock(*codec, opt, phase0));
  } else {
    if ((opt.cycles > 0) == (opt.period > 0))
      throw InputError({"", 0, "--cycles"}, "give exactly one of --cycles and --period");
    SequenceBlock ps;
    ps.type = BlockType::kPhaseShift;
    ps.steps = opt.steps;
    ps.cycles = {opt.cycles > 0 ? opt.cycles : m.Extent() / opt.period};
    ps.phase_at_origin_rad = phase0;
    m.sequence.push_back(ps);
    if (opt.scheme == "gray_code" || opt.scheme == "complementary_gray_code") {
      SequenceBlock gc;
      gc.type = BlockType::kGrayCode;
      gc.complementary = opt.scheme == "complementary_gray_code";
      gc.bits = static_cast<int>(std::lround(std::log2(ps.cycles[0]))) + (gc.complementary ? 1 : 0);
      m.sequence.push_back(gc);
    } else if (opt.scheme != "phase_shift") {
      throw InputError(
          {"", 0, "--scheme"},
          "expected phase_shift, gray_code, complementary_gray_code or an absolute codec (" + AbsoluteCodecNames() +
              "), got '" + opt.scheme + "'");
    }
  }
  m.path = (std::filesystem::path(opt.out) / "manifest.json").string();
  m.cameras["projector"].resize(m.ImageCount());
  m.Check();
  WritePatternSet(opt.out, m, opt.bits, opt.force, &provenance);
  std::cout << "wrote " << m.ImageCount() << " " << opt.bits << "-bit patterns and manifest.json to " << opt.out
            << "\n";
  return kExitOk;
}

}  // namespace

void RegisterPatternsCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<PatternsCommandOptions>();
  CLI::App* sub = app.add_subcommand("patterns", "Write fringe projector patterns (PNG) and their manifest");
  sub->add_option("--scheme", opt->scheme,
                  "phase_shift | gray_code | complementary_gray_code | an absolute codec: " + AbsoluteCodecNames())
      ->capture_default_str();
  sub->add_option("--width", opt->width, "Projector width, px")->capture_default_str();
  sub->add_option("--height", opt->height, "Projector height, px")->capture_default_str();
  sub->add_option("--direction", opt->direction, "vertical (codes columns) or horizontal (codes rows) fringes")
      ->capture_default_str();
  sub->add_option("--steps", opt->steps, "Phase steps N >= 3 (per frequency)")->capture_default_str();
  sub->add_option("--cycles", opt->cycles, "Fringe periods across the projector (a power of 2 with Gray code)");
  sub->add_option("--period", opt->period, "Fringe period in projector px (instead of --cycles)");
  sub->add_option("--heterodyne-cycles", opt->heterodyne, "Heterodyne cycles, finest first")->capture_default_str();
  sub->add_option("--phase-at-origin", opt->phase_at_origin_deg, "Phase at projector pixel 0, degrees")
      ->capture_default_str();
  sub->add_option("--bits", opt->bits, "PNG bit depth: 8 or 16")->capture_default_str();
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_flag("--force", opt->force, "Replace an existing non-empty output folder (once the new set is complete)");
  sub->footer(vision::PatternCodecHelp());
  sub->callback([opt, exit_code, sub]() { *exit_code = RunPatterns(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
