// Projector calibration files (projector_calibration.h).
#include "ramtk/vision/projector/projector_calibration.h"

#include <regex>
#include <sstream>
#include <utility>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace ramtk::vision {
namespace {

// The top-level keys of an OpenCV YAML text, each with its block of lines (the key's line and the
// indented or continuation lines after it), in file order.
std::vector<std::pair<std::string, std::string>> TopLevelYamlBlocks(const std::string& text) {
  static const std::regex key_line(R"(^([A-Za-z_][A-Za-z0-9_]*)\s*:.*)");
  std::vector<std::pair<std::string, std::string>> blocks;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, key_line)) {
      blocks.emplace_back(m[1].str(), line.substr(m[1].length()) + "\n");
    } else if (!blocks.empty() && !line.empty() && (line[0] == ' ' || line[0] == '\t')) {
      blocks.back().second += line + "\n";
    }
  }
  return blocks;
}

bool HasKey(const std::vector<std::pair<std::string, std::string>>& blocks, const std::string& key) {
  for (const auto& b : blocks)
    if (b.first == key) return true;
  return false;
}

// SLMaster's monocular keys as ramtk's stereo keys: M1 D1 S kept, M4 D4 Rlp Tlp renamed to M2 D2
// R T, every other key (its binocular and rectification extras) left out.
std::string SlmasterMonocularAsStereo(const std::vector<std::pair<std::string, std::string>>& blocks) {
  static const std::vector<std::pair<std::string, std::string>> kRename = {
      {"M1", "M1"}, {"D1", "D1"}, {"S", "S"}, {"M4", "M2"}, {"D4", "D2"}, {"Rlp", "R"}, {"Tlp", "T"}};
  std::string out = "%YAML:1.0\n---\n";
  for (const auto& [from, to] : kRename)
    for (const auto& [key, body] : blocks)
      if (key == from) out += to + body;
  return out;
}

}  // namespace

StereoCalibration AsStereoPair(const ProjectorCalibration& c) {
  StereoCalibration s;
  s.left = c.camera;
  s.right = c.projector;
  s.right_from_left = c.projector_from_camera;
  s.rms_px = c.rms_px;
  s.parameter_std = c.parameter_std;
  return s;
}

ProjectorCalibration FromStereoPair(const StereoCalibration& s) {
  ProjectorCalibration c;
  c.camera = s.left;
  c.projector = s.right;
  c.projector_from_camera = s.right_from_left;
  c.rms_px = s.rms_px;
  c.parameter_std = s.parameter_std;
  return c;
}

ProjectorCalibration ParseProjectorCalibration(const std::string& text, const std::string& path, int projector_width,
                                               int projector_height) {
  const bool json = text.find_first_not_of(" \t\r\n") != std::string::npos &&
                    text[text.find_first_not_of(" \t\r\n")] == '{';
  bool has_projector_size = json && text.find("\"image_size2\"") != std::string::npos;
  StereoCalibration pair;
  if (!json) {
    const auto blocks = TopLevelYamlBlocks(text);
    has_projector_size = HasKey(blocks, "image_size2");
    if (HasKey(blocks, "M4") && HasKey(blocks, "Rlp")) {
      pair = ParseStereoCalibration(SlmasterMonocularAsStereo(blocks), path);
    } else {
      pair = ParseStereoCalibration(text, path);
    }
  } else {
    pair = ParseStereoCalibration(text, path);
  }
  if (projector_width > 0 && projector_height > 0) {
    pair.right.width = projector_width;
    pair.right.height = projector_height;
  } else if (!has_projector_size) {
    throw InputError({path, 0, "image_size2"},
                     "the file gives no projector resolution (image_size2) and none was given (the manifest's "
                     "projector width and height)");
  }
  return FromStereoPair(pair);
}

ProjectorCalibration ReadProjectorCalibration(const std::string& path, int projector_width, int projector_height) {
  RequireRegularFile(path);
  return ParseProjectorCalibration(ReadTextFile(path), path, projector_width, projector_height);
}

void WriteProjectorCalibration(const std::string& path, const ProjectorCalibration& calibration) {
  WriteStereoCalibration(path, AsStereoPair(calibration));
}

}  // namespace ramtk::vision
