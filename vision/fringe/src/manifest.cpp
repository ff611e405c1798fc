// Fringe image set manifest: JSON read/write and validation.
#include "ramtk/vision/fringe/manifest.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/manifest_builder.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

using nlohmann::json;

[[noreturn]] void Fail(const std::string& file, const std::string& field, const std::string& message) {
  throw InputError({file, 0, field}, message);
}

// The values of a kCycles parameter (or its period key, converted to cycles across `extent`).
std::vector<double> ParseCycles(const json& b, const CodecParameter& p, const std::string& file,
                                const std::string& where, int extent) {
  const bool has_cycles = b.contains(p.key);
  const bool has_period = !p.period_key.empty() && b.contains(p.period_key);
  if (has_cycles == has_period) {
    if (p.period_key.empty()) Fail(file, where + p.key, "is required");
    Fail(file, where + p.key, "give exactly one of '" + p.key + "' and '" + p.period_key + "'");
  }
  const std::string key = has_cycles ? p.key : p.period_key;
  const json& v = b.at(key);
  std::vector<double> values;
  if (p.max_count == 1) {
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
  return values;
}

// One parameter of the block's codec from the JSON object (absent optional keys keep the default).
void ParseParameter(const json& b, const CodecParameter& p, const std::string& file, const std::string& where,
                    int extent, SequenceBlock* block) {
  if (p.field == CodecField::kCycles) {
    block->cycles = ParseCycles(b, p, file, where, extent);
    return;
  }
  if (!b.contains(p.key)) {
    if (p.required) JsonRequire(b, p.key, file, where);
    return;
  }
  const json& v = b.at(p.key);
  switch (p.field) {
    case CodecField::kSteps:
      block->steps = JsonInt(v, file, where + p.key);
      break;
    case CodecField::kBits:
      block->bits = JsonInt(v, file, where + p.key);
      break;
    case CodecField::kComplementary:
      if (!v.is_boolean()) Fail(file, where + p.key, "expected true or false");
      block->complementary = v.get<bool>();
      break;
    case CodecField::kPhaseAtOrigin: {
      const double deg = JsonNumber(v, file, where + p.key);
      // One turn either way covers every convention; beyond it is a corrupt value (1e308 would
      // decode to "valid" pixels without one finite coordinate).
      if (!(std::abs(deg) <= 360.0)) Fail(file, where + p.key, "must be within [-360, 360] degrees");
      block->phase_at_origin_rad = deg * kPi / 180.0;
      break;
    }
    case CodecField::kCycles:
      break;
  }
}

SequenceBlock ParseBlock(const json& b, const std::string& file, const std::string& where, int extent) {
  const std::string type = JsonRequire(b, "type", file, where).is_string() ? b.at("type").get<std::string>() : "";
  const PatternCodec* codec = FindPatternCodec(type);
  if (!codec) {
    std::string names;
    for (const PatternCodec* c : PatternCodecs()) names += (names.empty() ? "'" : ", '") + c->name + "'";
    Fail(file, where + "type", "expected one of " + names + ", got " + b.value("type", json()).dump());
  }
  SequenceBlock block;
  block.type = codec->type;
  if (codec->type == BlockType::kRegistered) block.codec = codec->name;
  for (const CodecParameter& p : codec->parameters) ParseParameter(b, p, file, where, extent, &block);
  return block;
}

// "" or `key: problem` for a value of a parameter outside its range.
std::string CheckParameter(const SequenceBlock& b, const CodecParameter& p) {
  auto out_of = [&](double v) { return !(v >= p.min && v <= p.max); };
  switch (p.field) {
    case CodecField::kSteps:
      if (out_of(b.steps)) return p.key + ": needs " + std::to_string(static_cast<int>(p.min)) + " or more, got " + std::to_string(b.steps);
      break;
    case CodecField::kBits:
      if (out_of(b.bits))
        return p.key + ": expected " + std::to_string(static_cast<int>(p.min)) + ".." +
               std::to_string(static_cast<int>(p.max)) + " code bits, got " + std::to_string(b.bits);
      break;
    case CodecField::kCycles:
      if (static_cast<int>(b.cycles.size()) < p.min_count || static_cast<int>(b.cycles.size()) > p.max_count)
        return p.key + ": expected " + std::to_string(p.min_count) + " to " + std::to_string(p.max_count) +
               " frequencies, got " + std::to_string(b.cycles.size());
      for (double c : b.cycles)
        if (!(c > p.min && c <= p.max)) return p.key + ": must be positive";
      break;
    case CodecField::kPhaseAtOrigin:
      if (out_of(b.phase_at_origin_rad * 180.0 / kPi)) return p.key + ": must be within [-360, 360] degrees";
      break;
    case CodecField::kComplementary:
      break;
  }
  return "";
}

// Fails naming `where` + the key a problem `key: what` starts with.
void FailProblem(const std::string& file, const std::string& where, const std::string& problem) {
  const std::size_t colon = problem.find(": ");
  Fail(file, where + problem.substr(0, colon), problem.substr(colon + 2));
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
    case BlockType::kRegistered:
      return "registered";
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

int SequenceBlock::ImageCount() const { return CodecOf(*this).image_count(*this); }

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
  for (const auto* list : {&cameras, &cross_cameras})
    for (const auto& [name, files] : *list)
      for (const std::string& f : files) out.push_back(Resolve(f));
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
  int n_phase = 0, n_order = 0, n_absolute = 0;
  const SequenceBlock* phase = nullptr;
  const SequenceBlock* order = nullptr;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const SequenceBlock& b = sequence[i];
    const std::string where = "sequence[" + std::to_string(i) + "].";
    if (b.type == BlockType::kRegistered && !FindPatternCodec(b.codec))
      Fail(path, where + "type", "no pattern codec '" + b.codec + "' is registered");
    const PatternCodec& codec = CodecOf(b);
    for (const CodecParameter& p : codec.parameters)
      if (const std::string problem = CheckParameter(b, p); !problem.empty()) FailProblem(path, where, problem);
    if (codec.check)
      if (const std::string problem = codec.check(b, Extent()); !problem.empty()) FailProblem(path, where, problem);
    if (codec.role == CodecRole::kPhase) ++n_phase, phase = &b;
    if (codec.role == CodecRole::kOrder) ++n_order, order = &b;
    if (codec.role == CodecRole::kAbsolute) ++n_absolute;
  }
  const bool ok = (n_absolute == 1 && n_phase == 0 && n_order == 0) || (n_absolute == 0 && n_phase == 1 && n_order <= 1);
  if (!ok)
    Fail(path, "sequence",
         "supported sequences: one absolute block (heterodyne or a registered codec), or one phase block "
         "(phase_shift) with at most one period-order block (gray_code)");
  if (phase && !order && phase->cycles.at(0) > 1.0 + 1e-9)
    Fail(path, "sequence", "a phase_shift block with more than one cycle needs a gray_code block to unwrap it");
  if (phase && order) {
    const PatternCodec& codec = CodecOf(*order);
    if (codec.check_with_phase)
      if (const std::string problem = codec.check_with_phase(*order, *phase); !problem.empty())
        FailProblem(path, "sequence." + codec.name + ".", problem);
  }
  if (cameras.empty()) Fail(path, "cameras", "no camera listed");
  for (const auto& [name, files] : cameras) {
    if (static_cast<int>(files.size()) != ImageCount())
      Fail(path, "cameras." + name,
           "the sequence needs " + std::to_string(ImageCount()) + " images, the camera lists " +
               std::to_string(files.size()));
  }
  for (const auto& [name, files] : cross_cameras) {
    if (!cameras.count(name)) Fail(path, "cross_cameras." + name, "no camera of that name in cameras");
    if (static_cast<int>(files.size()) != ImageCount())
      Fail(path, "cross_cameras." + name,
           "the sequence needs " + std::to_string(ImageCount()) + " images, the camera lists " +
               std::to_string(files.size()));
  }
}

FringeManifest FringeManifest::CrossDirection() const {
  FringeManifest m = *this;
  m.direction = direction == FringeDirection::kVertical ? FringeDirection::kHorizontal : FringeDirection::kVertical;
  m.cameras = cross_cameras;
  m.cross_cameras.clear();
  return m;
}

namespace {
// A manifest's {name: [files...]} object (`key`: "cameras" or "cross_cameras"); globs expanded in
// natural order (1, 2, 10), relative to the manifest's folder.
std::map<std::string, std::vector<std::string>> ParseCameraFiles(const json& cams, const std::string& path,
                                                                const std::string& key) {
  if (!cams.is_object()) Fail(path, key, "expected an object {name: [files...]}");
  std::map<std::string, std::vector<std::string>> out;
  for (const auto& [name, files] : cams.items()) {
    if (!files.is_array()) Fail(path, key + "." + name, "expected an array of image files");
    std::vector<std::string> list;
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string field = key + "." + name + "[" + std::to_string(i) + "]";
      if (!files[i].is_string()) Fail(path, field, "expected a file name");
      const std::string file = files[i].get<std::string>();
      if (!IsImageGlob(file)) {
        list.push_back(file);
        continue;
      }
      const std::vector<std::string> matched =
          ExpandImageGlob(file, std::filesystem::path(path).parent_path().string());
      if (matched.empty()) Fail(path, field, "no file matches " + file);
      list.insert(list.end(), matched.begin(), matched.end());
    }
    out[name] = list;
  }
  return out;
}
}  // namespace

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
  m.cameras = ParseCameraFiles(JsonRequire(j, "cameras", path, ""), path, "cameras");
  if (j.contains("cross_cameras")) m.cross_cameras = ParseCameraFiles(j.at("cross_cameras"), path, "cross_cameras");
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
    const PatternCodec& codec = CodecOf(b);
    json o;
    o["type"] = codec.name;
    for (const CodecParameter& p : codec.parameters) {
      switch (p.field) {
        case CodecField::kSteps:
          o[p.key] = b.steps;
          break;
        case CodecField::kBits:
          o[p.key] = b.bits;
          break;
        case CodecField::kComplementary:
          o[p.key] = b.complementary;
          break;
        case CodecField::kCycles:
          if (p.max_count == 1) {
            o[p.key] = b.cycles.at(0);
          } else {
            o[p.key] = b.cycles;
          }
          break;
        case CodecField::kPhaseAtOrigin:
          o[p.key] = b.phase_at_origin_rad * 180.0 / kPi;
          break;
      }
    }
    seq.push_back(o);
  }
  j["sequence"] = seq;
  json cams = json::object();
  for (const auto& [name, files] : m.cameras) cams[name] = files;
  j["cameras"] = cams;
  if (!m.cross_cameras.empty()) {
    json cross = json::object();
    for (const auto& [name, files] : m.cross_cameras) cross[name] = files;
    j["cross_cameras"] = cross;
  }
  return j.dump(2) + "\n";
}

void WriteFringeManifest(const std::string& path, const FringeManifest& manifest) {
  WriteFileAtomically(path, FringeManifestToJson(manifest));
}

}  // namespace ramtk::vision
