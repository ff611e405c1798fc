#pragma once
// Fringe image set manifest (DESIGN.md "Fringe image set"; docs/formats.md): a JSON file beside
// the images naming, per camera, the ordered image files, the pattern sequence that produced
// them, the fringe direction, the projector resolution and the stereo calibration file.
//
// Phase convention (shared by the pattern generator and the decoder): projector pixel index u
// (column for vertical fringes, row for horizontal ones) has phase
//   phi(u) = 2*pi*u/period + phase_at_origin
// and step k of an N-step block shows 0.5 + 0.5*cos(phi(u) + 2*pi*k/N). The default
// phase_at_origin = -180 deg makes every period start dark, which is the layout of SLMaster
// (shared/data/slmaster-binocular), so Gray-code cell edges coincide with period edges.
// Gray code (gray_code.h): cell c = floor(u * 2^bits / extent), gray = c ^ (c >> 1), image j (0 =
// most significant) shows bit (bits-1-j) of gray, white = 1. Complementary Gray code has one more
// bit than log2(cycles): its last image splits every period into halves.

#include <map>
#include <string>
#include <vector>

namespace ramtk::vision {

enum class FringeDirection {
  kVertical,    // vertical stripes: encode the projector column u (uses projector width)
  kHorizontal,  // horizontal stripes: encode the projector row v (uses projector height)
};

// The built-in codecs' blocks; kRegistered: a codec added at run time (codec.h), named by
// SequenceBlock::codec. Each codec's parameters, ranges and role are in its row of codec.h's table.
enum class BlockType { kPhaseShift, kGrayCode, kHeterodyne, kRegistered };

// One block of the projected sequence.
struct SequenceBlock {
  BlockType type = BlockType::kPhaseShift;
  // kRegistered: the codec's name (the manifest's "type"); "" for the built-in types.
  std::string codec;
  // phase_shift / heterodyne: phase steps per frequency (>= 3).
  int steps = 0;
  // phase_shift: one value; heterodyne: one per frequency, in projection order. Fringe periods
  // across the projector extent (cycles = extent / period_px).
  std::vector<double> cycles;
  // phase_shift / heterodyne: phase at projector pixel 0, radians (file: degrees).
  double phase_at_origin_rad = -3.14159265358979323846;
  // gray_code: number of code images.
  int bits = 0;
  // gray_code: true for complementary Gray code (one extra half-period bit).
  bool complementary = false;

  // Number of images this block occupies.
  int ImageCount() const;
};

// A phase-shift block: `steps` >= 3 images, `cycles` periods across the projector, phase at u = 0.
SequenceBlock PhaseShiftBlock(int steps, double cycles, double phase_at_origin_rad = -3.14159265358979323846);
// A heterodyne block: for each entry of `cycles` (finest first), `steps` phase-shift images.
SequenceBlock HeterodyneBlock(int steps, const std::vector<double>& cycles,
                              double phase_at_origin_rad = -3.14159265358979323846);
// A Gray-code block of `bits` images (complementary: the last bit splits each period in halves).
SequenceBlock GrayCodeBlock(int bits, bool complementary);

// "vertical" / "horizontal", as in the manifest file.
const char* FringeDirectionName(FringeDirection direction);

struct FringeManifest {
  // Path the manifest was read from ("" when built in memory). Relative image and calibration
  // paths are resolved against its folder.
  std::string path;
  int projector_width = 0;   // projector pixels
  int projector_height = 0;  // projector pixels
  FringeDirection direction = FringeDirection::kVertical;
  std::string calibration;              // stereo calibration file as written (may be "")
  // Camera–projector (monocular) set: the calibration of the camera and the projector as written
  // (vision/projector/projector_calibration.h; ramtk's or SLMaster's layout); "" for a stereo set.
  // With it, `ramtk scan` triangulates one camera against the projector.
  std::string projector_calibration;
  std::vector<SequenceBlock> sequence;  // in projection order
  // Camera name ("left", "right", ...) -> ordered image files as written in the manifest.
  std::map<std::string, std::vector<std::string>> cameras;
  // Camera–projector set with both fringe directions (JSON "cross_cameras"): camera name -> the
  // same sequence's image files projected with the fringes in the other direction; empty when only
  // `direction` was projected. With them `ramtk scan` triangulates ray–ray (the projector pixel).
  std::map<std::string, std::vector<std::string>> cross_cameras;

  // This set as projected in the other direction: `cross_cameras` as its cameras, the direction
  // flipped (Extent() then the other projector side), no cross cameras.
  FringeManifest CrossDirection() const;
  // Total images the sequence needs per camera.
  int ImageCount() const;
  // Projector pixels along the coded direction (width for vertical fringes).
  int Extent() const;
  // `file` resolved against the manifest's folder (absolute paths are kept).
  std::string Resolve(const std::string& file) const;
  // Every file this set is read from: the manifest itself, each camera's images and the
  // calibration files (resolved), so that commands can refuse outputs that would overwrite them.
  std::vector<std::string> InputFiles() const;
  // Throws InputError (file = path, field = the offending key) if the manifest is inconsistent:
  // bad counts, unsupported block combination, image count != sequence length. (A check of data
  // read from a file; options structs use the Validate() contract of core/error.h.)
  void Check() const;
};

// Largest projector side accepted (pixels): well above any real projector (4K is 3840), small
// enough that a typo cannot ask for terabytes of patterns.
inline constexpr int kMaxProjectorSide = 16384;

// Reads and validates a manifest. InputError names the file and the field.
FringeManifest ReadFringeManifest(const std::string& path);
// The same from the file's text; `path` names the file in errors and anchors relative paths.
FringeManifest ParseFringeManifest(const std::string& text, const std::string& path);
// JSON text of a manifest (the inverse of ReadFringeManifest).
std::string FringeManifestToJson(const FringeManifest& manifest);
// Writes the manifest atomically.
void WriteFringeManifest(const std::string& path, const FringeManifest& manifest);

// The built-in types' manifest names ("registered" for kRegistered: the block's codec names it).
const char* BlockTypeName(BlockType type);

}  // namespace ramtk::vision
