// Fringe image set manifest: JSON read/write and validation.
#include "ramtk/vision/fringe/manifest.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/vision/fringe/manifest_builder.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

using nlohmann::json;

[[noreturn]] void Fail(const std::string& file, const std::string& field, const std::string& message) {
  throw InputError({file, 0, field}, message);
}

bool IsPowerOfTwo(double c) {
  if (c < 1 || c != std::floor(c)) return false;
  const auto n = static_cast<long long>(c);
  return (n & (n - 1)) == 0;
}

SequenceBlock ParseBlock(const json& b, const std::string& file, const std::string& where, int extent) {
  SequenceBlock block;
  const std::string type = JsonRequire(b, "type", file, where).is_string() ? b.at("type").get<std::string>() : "";
  if (type == "phase_shift" || type == "heterodyne") {
    block.type = type == "phase_shift" ? BlockType::kPhaseShift : BlockType::kHeterodyne;
    block.steps = JsonInt(JsonRequire(b, "steps", file, where), file, where + "steps");
    const bool has_cycles = b.contains("cycles");
    const char* period_key = block.type == BlockType::kPhaseShift ? "period_px" : "periods_px";
    const bool has_period = b.contains(period_key);
    if (has_cycles == has_period)
      Fail(file, where + "cycles", std::string("give exactly one of 'cycles' and '") + period_key + "'");
    const std::string key = has_cycles ? "cycles" : period_key;
    const json& v = b.at(key);
    std::vector<double> values;
    if (block.type == BlockType::kPhaseShift) {
      values.push_back(JsonNumber(v, file, where + key));
    } else {
      if (!v.is_array()) Fail(file, where + key, "expected an array of numbers");
      for (std::size_t i = 0; i < v.size(); ++i)
        values.push_back(JsonNumber(v[i], file, where + key + "[" + std::to_string(i) + "]"));
    }
    for (double& x : values) {
      if (x <= 0) Fail(file, where + key, "must be positive");
      if (has_period) x = extent / x;  // period in px -> cycles across the projector
    }
    block.cycles = values;
    if (b.contains("phase_at_origin_deg")) {
      const double deg = JsonNumber(b.at("phase_at_origin_deg"), file, where + "phase_at_origin_deg");
      // One turn either way covers every convention; beyond it is a corrupt value (1e308 would
      // decode to "valid" pixels without one finite coordinate).
      if (!(std::abs(deg) <= 360.0)) Fail(file, where + "phase_at_origin_deg", "must be within [-360, 360] degrees");
      block.phase_at_origin_rad = deg * kPi / 180.0;
    }
  } else if (type == "gray_code") {
    block.type = BlockType::kGrayCode;
    block.bits = JsonInt(JsonRequire(b, "bits", file, where), file, where + "bits");
    if (b.contains("complementary")) {
      if (!b.at("complementary").is_boolean()) Fail(file, where + "complementary", "expected true or false");
      block.complementary = b.at("complementary").get<bool>();
    }
  } else {
    Fail(file, where + "type",
         "expected 'phase_shift', 'gray_code' or 'heterodyne', got " + b.value("type", json()).dump());
  }
  return block;
}

}  // namespace

const char* BlockTypeName(BlockType type) {
  switch (type) {
    case BlockType::kPhaseShift:
      return "phase_shift";
    case BlockType::kGrayCode:
      return "gray_code";
    case BlockType::kHeterodyne:
      return "heterodyne";
  }
  return "?";
}

const char* FringeDirectionName(FringeDirection direction) {
  return direction == FringeDirection::kVertical ? "vertical" : "horizontal";
}

SequenceBlock PhaseShiftBlock(int steps, double cycles, double phase_at_origin_rad) {
  SequenceBlock b;
  b.type = BlockType::kPhaseShift;
  b.steps = steps;
  b.cycles = {cycles};
  b.phase_at_origin_rad = phase_at_origin_rad;
  return b;
}

SequenceBlock HeterodyneBlock(int steps, const std::vector<double>& cycles, double phase_at_origin_rad) {
  SequenceBlock b;
  b.type = BlockType::kHeterodyne;
  b.steps = steps;
  b.cycles = cycles;
  b.phase_at_origin_rad = phase_at_origin_rad;
  return b;
}

SequenceBlock GrayCodeBlock(int bits, bool complementary) {
  SequenceBlock b;
  b.type = BlockType::kGrayCode;
  b.bits = bits;
  b.complementary = complementary;
  return b;
}

int SequenceBlock::ImageCount() const {
  switch (type) {
    case BlockType::kPhaseShift:
      return steps;
    case BlockType::kGrayCode:
      return bits;
    case BlockType::kHeterodyne:
      return steps * static_cast<int>(cycles.size());
  }
  return 0;
}

int FringeManifest::ImageCount() const {
  int n = 0;
  for (const SequenceBlock& b : sequence) n += b.ImageCount();
  return n;
}

int FringeManifest::Extent() const {
  return direction == FringeDirection::kVertical ? projector_width : projector_height;
}

std::string FringeManifest::Resolve(const std::string& file) const {
  const std::filesystem::path p(file);
  if (p.is_absolute() || path.empty()) return file;
  return (std::filesystem::path(path).parent_path() / p).lexically_normal().string();
}

std::vector<std::string> FringeManifest::InputFiles() const {
  std::vector<std::string> out;
  if (!path.empty()) out.push_back(path);
  for (const auto& [name, files] : cameras) {
    for (const std::string& f : files) out.push_back(Resolve(f));
  }
  if (!calibration.empty()) out.push_back(Resolve(calibration));
  if (!projector_calibration.empty()) out.push_back(Resolve(projector_calibration));
  return out;
}

void FringeManifest::Check() const {
  if (projector_width <= 0 || projector_height <= 0) Fail(path, "projector", "width and height must be positive");
  if (projector_width > kMaxProjectorSide || projector_height > kMaxProjectorSide) {
    Fail(path, "projector",
         "width and height must be at most " + std::to_string(kMaxProjectorSide) + " px (kMaxProjectorSide), got " +
             std::to_string(projector_width) + " x " + std::to_string(projector_height));
  }
  if (sequence.empty()) Fail(path, "sequence", "is empty");
  int n_ps = 0, n_gc = 0, n_het = 0;
  const SequenceBlock* ps = nullptr;
  const SequenceBlock* gc = nullptr;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const SequenceBlock& b = sequence[i];
    const std::string where = "sequence[" + std::to_string(i) + "].";
    if (b.type != BlockType::kGrayCode) {
      if (b.steps < 3) Fail(path, where + "steps", "needs at least 3 phase steps, got " + std::to_string(b.steps));
      for (double c : b.cycles)
        if (!(c > 0) || c > Extent() / 2.0)
          Fail(path, where + "cycles", "fringe period must be at least 2 projector pixels and positive");
    } else if (b.bits < 1 || b.bits > 16) {
      Fail(path, where + "bits", "expected 1..16 Gray-code bits, got " + std::to_string(b.bits));
    }
    if (b.type == BlockType::kPhaseShift) ++n_ps, ps = &b;
    if (b.type == BlockType::kGrayCode) ++n_gc, gc = &b;
    if (b.type == BlockType::kHeterodyne) {
      ++n_het;
      if (b.cycles.size() < 2 || b.cycles.size() > 3)
        Fail(path, where + "cycles", "heterodyne needs 2 or 3 frequencies");
      for (std::size_t k = 1; k < b.cycles.size(); ++k)
        if (!(b.cycles[k] < b.cycles[k - 1])) Fail(path, where + "cycles", "frequencies must decrease (finest first)");
      // The coarsest beat must cover the projector once: (c1-c2) for 2, (c1-c2)-(c2-c3) for 3.
      double beat = b.cycles[0] - b.cycles[1];
      if (b.cycles.size() == 3) beat -= b.cycles[1] - b.cycles[2];
      if (!(beat > 0) || beat > 1.0 + 1e-9)
        Fail(path, where + "cycles",
             "the beat of the frequencies must be in (0, 1] cycles across the projector (got " + std::to_string(beat) +
                 ")");
    }
  }
  const bool ok = (n_het == 1 && n_ps == 0 && n_gc == 0) || (n_het == 0 && n_ps == 1 && n_gc <= 1);
  if (!ok)
    Fail(path, "sequence",
         "supported sequences: one heterodyne block, or one phase_shift block with at most one gray_code block");
  if (ps && !gc && ps->cycles[0] > 1.0 + 1e-9)
    Fail(path, "sequence", "a phase_shift block with more than one cycle needs a gray_code block to unwrap it");
  if (ps && gc) {
    const int need = static_cast<int>(std::lround(std::log2(ps->cycles[0]))) + (gc->complementary ? 1 : 0);
    if (!IsPowerOfTwo(ps->cycles[0]) || gc->bits != need)
      Fail(path, "sequence.gray_code.bits",
           "a " + std::string(gc->complementary ? "complementary " : "") + "Gray code for " +
               std::to_string(ps->cycles[0]) + " cycles needs cycles = 2^k and bits = " +
               (gc->complementary ? "log2(cycles)+1" : "log2(cycles)") + " (got " + std::to_string(gc->bits) + ")");
  }
  if (cameras.empty()) Fail(path, "cameras", "no camera listed");
  for (const auto& [name, files] : cameras) {
    if (static_cast<int>(files.size()) != ImageCount())
      Fail(path, "cameras." + name,
           "the sequence needs " + std::to_string(ImageCount()) + " images, the camera lists " +
               std::to_string(files.size()));
  }
}

FringeManifest ReadFringeManifest(const std::string& path) { return ParseFringeManifest(ReadTextFile(path), path); }

FringeManifest ParseFringeManifest(const std::string& text, const std::string& path) {
  json j;
  j = ParseJsonText(text, path);
  FringeManifest m;
  m.path = path;
  const json& proj = JsonRequire(j, "projector", path, "");
  m.projector_width = JsonInt(JsonRequire(proj, "width", path, "projector."), path, "projector.width");
  m.projector_height = JsonInt(JsonRequire(proj, "height", path, "projector."), path, "projector.height");
  if (m.projector_width <= 0 || m.projector_height <= 0) Fail(path, "projector", "width and height must be positive");
  const json& dir = JsonRequire(j, "direction", path, "");
  if (dir == "vertical") {
    m.direction = FringeDirection::kVertical;
  } else if (dir == "horizontal") {
    m.direction = FringeDirection::kHorizontal;
  } else {
    Fail(path, "direction", "expected 'vertical' or 'horizontal', got " + dir.dump());
  }
  if (j.contains("calibration")) {
    if (!j.at("calibration").is_string()) Fail(path, "calibration", "expected a file name");
    m.calibration = j.at("calibration").get<std::string>();
  }
  if (j.contains("projector_calibration")) {
    if (!j.at("projector_calibration").is_string()) Fail(path, "projector_calibration", "expected a file name");
    m.projector_calibration = j.at("projector_calibration").get<std::string>();
  }
  const json& seq = JsonRequire(j, "sequence", path, "");
  if (!seq.is_array()) Fail(path, "sequence", "expected an array of blocks");
  for (std::size_t i = 0; i < seq.size(); ++i)
    m.sequence.push_back(ParseBlock(seq[i], path, "sequence[" + std::to_string(i) + "].", m.Extent()));
  const json& cams = JsonRequire(j, "cameras", path, "");
  if (!cams.is_object()) Fail(path, "cameras", "expected an object {name: [files...]}");
  for (const auto& [name, files] : cams.items()) {
    if (!files.is_array()) Fail(path, "cameras." + name, "expected an array of image files");
    std::vector<std::string> list;
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (!files[i].is_string()) Fail(path, "cameras." + name + "[" + std::to_string(i) + "]", "expected a file name");
      const std::string file = files[i].get<std::string>();
      if (!IsImageGlob(file)) {
        list.push_back(file);
        continue;
      }
      // A glob: its files in natural order (1, 2, 10), relative to the manifest's folder.
      const std::vector<std::string> matched =
          ExpandImageGlob(file, std::filesystem::path(path).parent_path().string());
      if (matched.empty()) Fail(path, "cameras." + name + "[" + std::to_string(i) + "]", "no file matches " + file);
      list.insert(list.end(), matched.begin(), matched.end());
    }
    m.cameras[name] = list;
  }
  m.Check();
  return m;
}

std::string FringeManifestToJson(const FringeManifest& m) {
  json j;
  j["format"] = "ramtk-fringe-set";
  j["version"] = 1;
  j["projector"] = {{"width", m.projector_width}, {"height", m.projector_height}};
  j["direction"] = FringeDirectionName(m.direction);
  if (!m.calibration.empty()) j["calibration"] = m.calibration;
  if (!m.projector_calibration.empty()) j["projector_calibration"] = m.projector_calibration;
  json seq = json::array();
  for (const SequenceBlock& b : m.sequence) {
    json o;
    o["type"] = BlockTypeName(b.type);
    if (b.type == BlockType::kGrayCode) {
      o["bits"] = b.bits;
      o["complementary"] = b.complementary;
    } else {
      o["steps"] = b.steps;
      if (b.type == BlockType::kPhaseShift) {
        o["cycles"] = b.cycles.at(0);
      } else {
        o["cycles"] = b.cycles;
      }
      o["phase_at_origin_deg"] = b.phase_at_origin_rad * 180.0 / kPi;
    }
    seq.push_back(o);
  }
  j["sequence"] = seq;
  json cams = json::object();
  for (const auto& [name, files] : m.cameras) cams[name] = files;
  j["cameras"] = cams;
  return j.dump(2) + "\n";
}

void WriteFringeManifest(const std::string& path, const FringeManifest& manifest) {
  WriteFileAtomically(path, FringeManifestToJson(manifest));
}

}  // namespace ramtk::vision
