#pragma once
// A projector calibration session (docs/formats.md "Projector calibration session"): a board held
// in several poses in front of one camera and one projector, each pose captured under fringes in
// both directions. `session.json` lists the poses; each pose names two fringe-set manifests
// (docs/formats.md "Fringe image set") of the same camera, one with vertical fringes (projector
// columns) and one with horizontal fringes (projector rows):
//   {"format": "ramtk-projector-session", "version": 1, "board": "chessboard:9x6:20",
//    "poses": [{"name": "pose00", "vertical": "pose00/vertical.json",
//               "horizontal": "pose00/horizontal.json"}, ...]}
// "board" is optional (the command's --board overrides it). Relative paths are resolved against
// the folder of session.json.

#include <string>
#include <vector>

namespace ramtk::calib {

struct ProjectorSessionPose {
  std::string name;        // label in reports ("pose00")
  std::string vertical;    // manifest of the vertical fringes, as written in the file
  std::string horizontal;  // manifest of the horizontal fringes, as written in the file
};

struct ProjectorSession {
  std::string path;   // session.json it was read from ("" when built in memory)
  std::string board;  // board description (board.h ParseBoardSpec), "" when the file has none
  std::vector<ProjectorSessionPose> poses;

  // `file` resolved against the folder of `path` (absolute paths are kept).
  std::string Resolve(const std::string& file) const;
};

// Reads session.json, or `path`/session.json when `path` is a folder. InputError naming the file
// and the field (e.g. "poses[3].horizontal") for a missing key, a wrong type, a duplicate pose
// name or fewer than one pose.
ProjectorSession ReadProjectorSession(const std::string& path);
// The same from the file's text; `path` names the file in errors and anchors relative paths.
ProjectorSession ParseProjectorSession(const std::string& text, const std::string& path);
// JSON text of a session (the inverse of ReadProjectorSession).
std::string ProjectorSessionJson(const ProjectorSession& session);

}  // namespace ramtk::calib
