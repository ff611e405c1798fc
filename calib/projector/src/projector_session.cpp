#include "ramtk/calib/projector/projector_session.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"

namespace ramtk::calib {

namespace fs = std::filesystem;
using nlohmann::json;

std::string ProjectorSession::Resolve(const std::string& file) const {
  const fs::path p(file);
  if (p.is_absolute() || path.empty()) return p.string();
  return (fs::path(path).parent_path() / p).lexically_normal().string();
}

ProjectorSession ReadProjectorSession(const std::string& path) {
  std::error_code ec;
  const std::string file = fs::is_directory(path, ec) ? (fs::path(path) / "session.json").string() : path;
  return ParseProjectorSession(ReadTextFile(file), file);
}

ProjectorSession ParseProjectorSession(const std::string& text, const std::string& path) {
  const json root = ParseJsonText(text, path);
  if (!root.is_object()) throw InputError({path, 0, ""}, "a projector session must be a JSON object");
  ProjectorSession session;
  session.path = path;
  if (root.contains("format") && root["format"] != "ramtk-projector-session")
    throw InputError({path, 0, "format"}, "must be \"ramtk-projector-session\"");
  if (root.contains("board")) {
    if (!root["board"].is_string()) throw InputError({path, 0, "board"}, "must be a string such as chessboard:9x6:20");
    session.board = root["board"].get<std::string>();
  }
  const json& poses = JsonRequire(root, "poses", path);
  if (!poses.is_array() || poses.empty()) throw InputError({path, 0, "poses"}, "must be a non-empty array of poses");
  std::set<std::string> names;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string where = "poses[" + std::to_string(i) + "]";
    ProjectorSessionPose pose;
    for (const auto& [key, out] : {std::pair<const char*, std::string*>{"name", &pose.name},
                                   {"vertical", &pose.vertical},
                                   {"horizontal", &pose.horizontal}}) {
      const json& value = JsonRequire(poses[i], key, path, where + ".");
      if (!value.is_string() || value.get<std::string>().empty())
        throw InputError({path, 0, where + "." + key}, "must be a non-empty string");
      *out = value.get<std::string>();
    }
    if (!names.insert(pose.name).second)
      throw InputError({path, 0, where + ".name"}, "pose name \"" + pose.name + "\" appears twice");
    session.poses.push_back(pose);
  }
  return session;
}

std::string ProjectorSessionJson(const ProjectorSession& session) {
  json poses = json::array();
  for (const ProjectorSessionPose& p : session.poses)
    poses.push_back({{"name", p.name}, {"vertical", p.vertical}, {"horizontal", p.horizontal}});
  json root = {{"format", "ramtk-projector-session"}, {"version", 1}};
  if (!session.board.empty()) root["board"] = session.board;
  root["poses"] = poses;
  return root.dump(2) + "\n";
}

}  // namespace ramtk::calib
