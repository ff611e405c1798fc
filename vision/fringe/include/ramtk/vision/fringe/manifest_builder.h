#pragma once
// Fringe-set manifests from a folder: the sequence from a short spec ("ps:12:64,cgc:7"), each
// camera's frames from a glob expanded in natural order (1, 2, 10), checked (frame count against
// the sequence, every image readable, all images one size) before anything is written. The
// manifest reader expands globs the same way (ParseFringeManifest).

#include <map>
#include <string>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/fringe/sequence_spec.h"  // ParseSequenceSpec, SequenceSpec

namespace ramtk::vision {

// True when `text` holds a glob character (* ? [).
bool IsImageGlob(const std::string& text);
// The regular files matching `pattern` (relative patterns against `base_dir`), in natural order,
// spelled as the pattern is (relative stays relative). Empty when nothing matches.
std::vector<std::string> ExpandImageGlob(const std::string& pattern, const std::string& base_dir);

struct ManifestBuildOptions {
  std::string folder;                               // the capture folder; globs are relative to it
  std::string sequence;                             // sequence spec, e.g. "ps:12:64,cgc:7"
  std::map<std::string, std::string> camera_globs;  // camera name -> glob; empty: L/R or left/right subfolders
  std::string calibration;                          // calibration file ("" = none)
  int projector_width = 0;                          // projector pixels (> 0)
  int projector_height = 0;                         // projector pixels (> 0)
  FringeDirection direction = FringeDirection::kVertical;
  std::string output;  // manifest path: file names are written relative to its folder

  std::string Validate() const;  // empty if valid
};

struct ManifestBuildSummary {
  std::map<std::string, int> frames;  // per camera
  std::map<std::string, std::string> globs;  // per camera, the glob used
  int width = 0, height = 0;          // the images' size
  std::string BriefReport() const;
};

// The checked manifest. InputError naming the camera: a glob matching no file, a frame count
// that differs from the sequence's, an unreadable image, an image of another size.
FringeManifest BuildFringeManifest(const ManifestBuildOptions& options, ManifestBuildSummary* summary = nullptr);

}  // namespace ramtk::vision
