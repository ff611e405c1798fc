// The pattern codec table (codec.h): the built-in rows (phase shift, Gray code, heterodyne) and
// the codecs registered at run time.
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/gray_code.h"
#include "ramtk/vision/fringe/patterns.h"

namespace ramtk::vision {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;
constexpr double kInf = std::numeric_limits<double>::infinity();

CodecParameter Steps() { return {"steps", CodecField::kSteps, true, 3, kInf, 1, 1, "", "phase steps N per frequency"}; }
CodecParameter PhaseAtOrigin() {
  return {"phase_at_origin_deg",
          CodecField::kPhaseAtOrigin,
          false,
          -360,
          360,
          1,
          1,
          "",
          "phase at projector pixel 0, degrees (default -180: every period starts dark)"};
}

// Step k of frequency `cycles`: 0.5 + 0.5 cos(phi(u) + 2 pi k / N).
double PhaseShiftIntensity(const SequenceBlock& b, double cycles, int k, double u, int extent) {
  const double shift = kTwoPi * k / b.steps;
  return 0.5 + 0.5 * std::cos(PatternPhase(u, cycles, extent, b.phase_at_origin_rad) + shift);
}

// Every frequency's period at least 2 projector pixels.
std::string CheckPeriods(const SequenceBlock& b, int extent) {
  for (double c : b.cycles)
    if (!(c > 0) || c > extent / 2.0) return "cycles: fringe period must be at least 2 projector pixels and positive";
  return "";
}

PatternCodec PhaseShiftCodec() {
  PatternCodec c;
  c.name = "phase_shift";
  c.type = BlockType::kPhaseShift;
  c.role = CodecRole::kPhase;
  c.spec_name = "ps";
  c.help = "N-step phase shift: image k shows 0.5 + 0.5 cos(2 pi cycles u / extent + phase_at_origin + 2 pi k / N)";
  c.parameters = {Steps(),
                  {"cycles", CodecField::kCycles, true, 0, kInf, 1, 1, "period_px",
                   "fringe periods across the projector (or period_px: the period in projector px)"},
                  PhaseAtOrigin()};
  c.image_count = [](const SequenceBlock& b) { return b.steps; };
  c.intensity = [](const SequenceBlock& b, int image, double u, int extent) {
    return PhaseShiftIntensity(b, b.cycles.at(0), image, u, extent);
  };
  c.check = CheckPeriods;
  return c;
}

PatternCodec GrayCodeCodec() {
  PatternCodec c;
  c.name = "gray_code";
  c.type = BlockType::kGrayCode;
  c.role = CodecRole::kOrder;
  c.spec_name = "gc";
  c.help = "Gray code of the period order: image j shows bit (bits - 1 - j) of the cell's code word (gray_code.h)";
  c.parameters = {{"bits", CodecField::kBits, true, 1, 16, 1, 1, "", "code images"},
                  {"complementary", CodecField::kComplementary, false, 0, 1, 1, 1, "",
                   "one extra bit splitting every period in halves (default false)", "c"}};
  c.image_count = [](const SequenceBlock& b) { return b.bits; };
  c.intensity = [](const SequenceBlock& b, int image, double u, int extent) {
    return static_cast<double>(GrayCodeImageBit(GrayCodeWord(GrayCodeCell(u, b.bits, extent)), b.bits, image));
  };
  c.check_with_phase = [](const SequenceBlock& gc, const SequenceBlock& ps) -> std::string {
    const double cycles = ps.cycles.at(0);
    const int need = static_cast<int>(std::lround(std::log2(cycles))) + (gc.complementary ? 1 : 0);
    const bool power_of_two = cycles >= 1 && cycles == std::floor(cycles) &&
                              (static_cast<long long>(cycles) & (static_cast<long long>(cycles) - 1)) == 0;
    if (power_of_two && gc.bits == need) return "";
    return "bits: a " + std::string(gc.complementary ? "complementary " : "") + "Gray code for " +
           std::to_string(cycles) +
           " cycles needs cycles = 2^k and bits = " + (gc.complementary ? "log2(cycles)+1" : "log2(cycles)") +
           " (got " + std::to_string(gc.bits) + ")";
  };
  return c;
}

PatternCodec HeterodyneCodec() {
  PatternCodec c;
  c.name = "heterodyne";
  c.type = BlockType::kHeterodyne;
  c.role = CodecRole::kAbsolute;
  c.spec_name = "het";
  c.help =
      "multi-frequency phase shift, finest first: N steps per frequency; the beat of the frequencies "
      "((c1-c2) or (c1-c2)-(c2-c3)) covers the projector once";
  c.parameters = {Steps(),
                  {"cycles", CodecField::kCycles, true, 0, kInf, 2, 3, "periods_px",
                   "fringe periods across the projector per frequency, decreasing (or periods_px)"},
                  PhaseAtOrigin()};
  c.image_count = [](const SequenceBlock& b) { return b.steps * static_cast<int>(b.cycles.size()); };
  c.intensity = [](const SequenceBlock& b, int image, double u, int extent) {
    return PhaseShiftIntensity(b, b.cycles.at(image / b.steps), image % b.steps, u, extent);
  };
  c.check = [](const SequenceBlock& b, int extent) -> std::string {
    if (std::string p = CheckPeriods(b, extent); !p.empty()) return p;
    for (std::size_t k = 1; k < b.cycles.size(); ++k)
      if (!(b.cycles[k] < b.cycles[k - 1])) return "cycles: frequencies must decrease (finest first)";
    // The coarsest beat must cover the projector once: (c1-c2) for 2, (c1-c2)-(c2-c3) for 3.
    double beat = b.cycles[0] - b.cycles[1];
    if (b.cycles.size() == 3) beat -= b.cycles[1] - b.cycles[2];
    if (!(beat > 0) || beat > 1.0 + 1e-9)
      return "cycles: the beat of the frequencies must be in (0, 1] cycles across the projector (got " +
             std::to_string(beat) + ")";
    return "";
  };
  return c;
}

std::deque<PatternCodec>& Table() {
  static std::deque<PatternCodec> table{PhaseShiftCodec(), GrayCodeCodec(), HeterodyneCodec()};
  return table;
}
constexpr std::size_t kBuiltIn = 3;

std::string Number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

const char* RoleName(CodecRole role) {
  switch (role) {
    case CodecRole::kPhase:
      return "phase";
    case CodecRole::kOrder:
      return "period order";
    case CodecRole::kAbsolute:
      return "absolute";
  }
  return "?";
}

}  // namespace

// "integer >= 3", "number > 0", "2..3 numbers > 0", "true/false", "number in [-360, 360]".
std::string CodecParameterAccepted(const CodecParameter& p) {
  if (p.field == CodecField::kComplementary) return "true/false";
  const bool integer = p.field == CodecField::kSteps || p.field == CodecField::kBits;
  std::string what = integer ? "integer" : "number";
  if (p.field == CodecField::kCycles) {
    what = p.max_count > 1 ? "array of " + std::to_string(p.min_count) + ".." + std::to_string(p.max_count) + " numbers"
                           : "number";
    if (std::isinf(p.max)) return what + " > " + Number(p.min);
  }
  if (std::isinf(p.max)) return what + " >= " + Number(p.min);
  if (integer) return what + " " + Number(p.min) + ".." + Number(p.max);
  return what + " in [" + Number(p.min) + ", " + Number(p.max) + "]";
}

std::vector<const PatternCodec*> PatternCodecs() {
  std::vector<const PatternCodec*> out;
  for (const PatternCodec& c : Table()) out.push_back(&c);
  return out;
}

const PatternCodec* FindPatternCodec(const std::string& name) {
  for (const PatternCodec& c : Table())
    if (c.name == name) return &c;
  return nullptr;
}

const PatternCodec& CodecOf(const SequenceBlock& block) {
  if (block.type != BlockType::kRegistered) {
    for (const PatternCodec& c : Table())
      if (c.type == block.type) return c;
  } else if (const PatternCodec* c = FindPatternCodec(block.codec)) {
    return *c;
  }
  throw InputError({"", 0, "sequence"}, "no pattern codec '" + block.codec + "' is registered");
}

void RegisterPatternCodec(PatternCodec codec) {
  const InputLocation where{"", 0, "codec " + codec.name};
  if (codec.name.empty()) throw InputError(where, "a codec needs a name");
  if (FindPatternCodec(codec.name)) throw InputError(where, "a codec of this name exists");
  if (!codec.image_count || !codec.intensity) throw InputError(where, "a codec needs image_count and intensity");
  if (codec.role == CodecRole::kAbsolute && !codec.decode) throw InputError(where, "an absolute codec needs decode");
  if (codec.role != CodecRole::kAbsolute)
    throw InputError(where, "registered codecs give the absolute coordinate (role kAbsolute)");
  codec.type = BlockType::kRegistered;
  Table().push_back(std::move(codec));
}

bool UnregisterPatternCodec(const std::string& name) {
  std::deque<PatternCodec>& table = Table();
  for (std::size_t i = kBuiltIn; i < table.size(); ++i) {
    if (table[i].name != name) continue;
    table.erase(table.begin() + static_cast<std::ptrdiff_t>(i));
    return true;
  }
  return false;
}

SequenceBlock RegisteredBlock(const std::string& codec_name) {
  SequenceBlock b;
  b.type = BlockType::kRegistered;
  b.codec = codec_name;
  return b;
}

std::string PatternCodecTableMarkdown() {
  std::string s = "| codec (`type`) | role | parameters: accepted values | what it projects |\n|---|---|---|---|\n";
  for (const PatternCodec& c : Table()) {
    std::string params;
    for (const CodecParameter& p : c.parameters) {
      params += (params.empty() ? "" : "; ") + std::string("`") + p.key + "`";
      if (!p.period_key.empty()) params += " or `" + p.period_key + "`";
      params += ": " + CodecParameterAccepted(p) + (p.required ? "" : ", optional") + " — " + p.help;
    }
    s += "| `" + c.name + "` | " + RoleName(c.role) + " | " + params + " | " + c.help + " |\n";
  }
  return s;
}

std::string PatternCodecHelp() {
  std::string s = "Pattern codecs (manifest sequence block types):\n";
  for (const PatternCodec& c : Table()) {
    s += "  " + c.name + " (" + RoleName(c.role) + "): " + c.help + "\n";
    for (const CodecParameter& p : c.parameters) {
      s += "    " + p.key + (p.period_key.empty() ? "" : " | " + p.period_key) + ": " + CodecParameterAccepted(p) +
           (p.required ? "" : ", optional") + " - " + p.help + "\n";
    }
  }
  return s;
}

}  // namespace ramtk::vision
