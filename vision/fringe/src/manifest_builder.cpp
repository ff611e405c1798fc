// Fringe-set manifests from a folder, a sequence spec and camera globs.
#include "ramtk/vision/fringe/manifest_builder.h"

#include <glob.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "ramtk/core/natural_sort.h"
#include "ramtk/core/parse.h"
#include "ramtk/image/image_file.h"

namespace ramtk::vision {
namespace {

// Default camera globs: the L/R or left/right subfolders of the capture folder.
std::map<std::string, std::string> DefaultGlobs(const std::string& folder) {
  namespace fs = std::filesystem;
  for (const auto& [l, r] : {std::pair<const char*, const char*>{"L", "R"}, {"left", "right"}}) {
    if (fs::is_directory(fs::path(folder) / l)) {
      std::map<std::string, std::string> g = {{"left", std::string(l) + "/*"}};
      if (fs::is_directory(fs::path(folder) / r)) g["right"] = std::string(r) + "/*";
      return g;
    }
  }
  throw InputError({folder, 0, "--left"},
                   "no L/R or left/right subfolder: give the cameras' images with --left GLOB [--right GLOB]");
}

}  // namespace

bool IsImageGlob(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

std::vector<std::string> ExpandImageGlob(const std::string& pattern, const std::string& base_dir) {
  const bool relative = !std::filesystem::path(pattern).is_absolute();
  const std::string prefix = relative && !base_dir.empty() ? base_dir + "/" : "";
  glob_t g;
  std::vector<std::string> files;
  if (glob((prefix + pattern).c_str(), 0, nullptr, &g) == 0) {
    for (std::size_t i = 0; i < g.gl_pathc; ++i) {
      const std::string path = g.gl_pathv[i];
      struct stat st;
      if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
      files.push_back(path.substr(prefix.size()));
    }
  }
  globfree(&g);
  SortNaturally(&files);
  return files;
}

std::string ManifestBuildOptions::Validate() const {
  if (folder.empty()) return "folder: give the capture folder";
  if (sequence.empty()) return "sequence: give the sequence, e.g. ps:12:64,cgc:7";
  if (projector_width <= 0 || projector_height <= 0)
    return "projector: give the projector resolution as WxH (e.g. 1280x720)";
  if (output.empty()) return "output: give the manifest path";
  return "";
}

std::string ManifestBuildSummary::BriefReport() const {
  std::ostringstream s;
  s << "manifest:";
  for (const auto& [name, n] : frames) s << " " << name << " " << n << " frames (" << globs.at(name) << ")";
  s << ", " << width << "x" << height << " px, every image read";
  return s.str();
}

FringeManifest BuildFringeManifest(const ManifestBuildOptions& options, ManifestBuildSummary* summary) {
  ThrowIfInvalid(options.Validate(), "ManifestBuildOptions");
  namespace fs = std::filesystem;
  if (!fs::is_directory(options.folder)) throw InputError({options.folder, 0, "folder"}, "not a folder");
  FringeManifest m;
  m.projector_width = options.projector_width;
  m.projector_height = options.projector_height;
  m.direction = options.direction;
  m.sequence = ParseSequenceSpec(options.sequence, {"", 0, "--sequence"});
  const fs::path out_dir = fs::absolute(fs::path(options.output)).parent_path();
  auto relative_to_output = [&](const fs::path& p) {
    return fs::absolute(p).lexically_normal().lexically_relative(out_dir.lexically_normal()).generic_string();
  };
  if (!options.calibration.empty()) {
    if (!fs::is_regular_file(options.calibration))
      throw InputError({options.calibration, 0, "--calib"}, "no such calibration file");
    m.calibration = relative_to_output(options.calibration);
  }
  ManifestBuildSummary s;
  const std::map<std::string, std::string> globs =
      options.camera_globs.empty() ? DefaultGlobs(options.folder) : options.camera_globs;
  const int needed = m.ImageCount();
  for (const auto& [name, pattern] : globs) {
    const std::string field = "--" + name;
    const std::vector<std::string> files = ExpandImageGlob(pattern, options.folder);
    if (static_cast<int>(files.size()) != needed)
      throw InputError({options.folder, 0, field}, std::to_string(files.size()) + " files match '" + pattern +
                                                       "', the sequence " + options.sequence + " needs " +
                                                       std::to_string(needed));
    std::vector<std::string>& list = m.cameras[name];
    for (const std::string& f : files) {
      const fs::path path = fs::path(options.folder) / f;
      int bits = 0;
      const cv::Mat img = image::LoadImageDn(path.string(), &bits);  // InputError names an unreadable file
      if (s.width == 0) s.width = img.cols, s.height = img.rows;
      if (img.cols != s.width || img.rows != s.height)
        throw InputError({path.string(), 0, field}, "image size " + std::to_string(img.cols) + "x" +
                                                        std::to_string(img.rows) + " differs from " +
                                                        std::to_string(s.width) + "x" + std::to_string(s.height));
      list.push_back(relative_to_output(path));
    }
    s.frames[name] = needed;
    s.globs[name] = pattern;
  }
  m.path = options.output;
  m.Check();
  if (summary) *summary = s;
  return m;
}

}  // namespace ramtk::vision
