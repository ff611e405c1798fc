// ramtk_indep_gen: independent data generators for `ramtk diagnose` (issue 15). See README.md.
//   ramtk_indep_gen --kind fringe|robot|laser --effect NAME --seed N [--magnitude X] [--gain G]
//                   [--robot FILE] --out DIR
#include "common.h"
#include "fringe_gen.h"
#include "laser_gen.h"
#include "robot_gen.h"

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <string>

namespace {

constexpr const char* kUsage =
    "usage: ramtk_indep_gen --kind fringe|robot|laser --effect NAME --seed N [--magnitude X] [--gain G]\n"
    "                       [--robot FILE] --out DIR\n"
    "  fringe effects: none camera_defocus soft_knee_response projector_nonlinearity phase_shift_error defocus\n"
    "  robot effects:  none joint_compliance joint_cyclic_error link_length_error thermal_length_drift joint_offset\n"
    "  laser effects:  none beam_non_perpendicular speed_ripple\n"
    "  --magnitude: effect size (units and defaults in tests/independent/README.md)\n"
    "  --gain: fringe camera conversion gain, DN (16-bit) per electron (default 1)\n"
    "  --sub: fringe rays per camera pixel along each axis (default 2; 1 = point sampling)\n"
    "Writes the data files and DIR/truth.json (expected verdict).\n";

double ParseNumber(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0') throw std::runtime_error(flag + ": expected a number, got '" + text + "'");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  indep::GenOptions o;
#ifdef INDEP_DEFAULT_ROBOT
  o.robot_path = INDEP_DEFAULT_ROBOT;
#endif
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        std::cout << kUsage;
        return 0;
      }
      if (i + 1 >= argc) throw std::runtime_error(a + ": missing value");
      const char* v = argv[++i];
      if (a == "--kind") o.kind = v;
      else if (a == "--effect") o.effect = v;
      else if (a == "--seed") o.seed = static_cast<unsigned>(ParseNumber(a, v));
      else if (a == "--magnitude") o.magnitude = ParseNumber(a, v);
      else if (a == "--gain") o.gain = ParseNumber(a, v);
      else if (a == "--sub") o.sub = static_cast<int>(ParseNumber(a, v));
      else if (a == "--out") o.out_dir = v;
      else if (a == "--robot") o.robot_path = v;
      else throw std::runtime_error("unknown option " + a);
    }
    if (o.kind.empty() || o.effect.empty() || o.out_dir.empty()) {
      throw std::runtime_error("--kind, --effect and --out are required");
    }
    if (!(o.gain > 0)) throw std::runtime_error("--gain must be > 0");
    if (o.sub < 1 || o.sub > 8) throw std::runtime_error("--sub must be in 1..8");
    if (o.kind == "robot") indep::GenerateRobot(o);
    else if (o.kind == "fringe") indep::GenerateFringe(o);
    else if (o.kind == "laser") indep::GenerateLaser(o);
    else throw std::runtime_error("--kind: expected fringe, robot or laser, got '" + o.kind + "'");
  } catch (const std::exception& e) {
    std::cerr << "ramtk_indep_gen: " << e.what() << "\n" << kUsage;
    return 2;
  }
  return 0;
}
