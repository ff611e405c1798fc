#pragma once
// The pattern codecs: one row per kind of sequence block (the manifest's "type"), with its
// parameters and their ranges, its role in the decode and how it draws its images. The manifest
// reader and writer (manifest.cpp), the pattern generator (patterns.cpp: `ramtk patterns`), the
// simulator's renderer, the decoder's dispatch (decode.cpp), `ramtk patterns --help` and the
// codec table of docs/formats.md (checked by tests/vision/codec_table_test.cpp) all read it.
// The built-in rows are in codec_table.cpp; RegisterPatternCodec adds one at run time.

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {

// What a block gives the decoder.
enum class CodecRole {
  kPhase,     // the wrapped phase of the finest fringe; beyond one period it needs a kOrder block
  kOrder,     // the period order of the kPhase block
  kAbsolute,  // the absolute projector coordinate on its own
};

// The SequenceBlock field a manifest parameter fills.
enum class CodecField {
  kSteps,          // SequenceBlock::steps (integer)
  kCycles,         // SequenceBlock::cycles (a number, or an array when max_count > 1)
  kBits,           // SequenceBlock::bits (integer)
  kComplementary,  // SequenceBlock::complementary (true / false)
  kPhaseAtOrigin,  // SequenceBlock::phase_at_origin_rad (the file gives degrees)
};

struct CodecParameter {
  std::string key;                        // manifest key
  CodecField field = CodecField::kSteps;  // the SequenceBlock field it fills
  bool required = true;                   // false: the SequenceBlock default stays when the key is absent
  // Accepted values, inclusive (kCycles: above min, each entry of an array; unused for booleans).
  double min = 0, max = 0;
  int min_count = 1, max_count = 1;  // kCycles: how many values (1: a number in the file, else an array)
  std::string period_key;            // kCycles: the key giving periods in projector px instead ("" = none)
  std::string help;                  // one line: docs/formats.md and `ramtk patterns --help`
  // kComplementary: the prefix on the block's name in a sequence spec that sets it ("c": cgc:7).
  std::string spec_prefix;
};

// The decode of a kAbsolute codec the fused decoder does not run itself.
struct CodecDecodeResult {
  cv::Mat coordinate;        // CV_32F projector px along the coded direction, NaN where not decoded
  cv::Mat modulation;        // CV_32F signal amplitude, DN
  cv::Mat sigma_coordinate;  // CV_32F sigma of the coordinate, projector px (NaN where not decoded)
};
// `frames`: the block's images in order, CV_32F in DN; `full_scale`: the sensor's largest value.
using CodecDecodeFunction = std::function<CodecDecodeResult(
    const SequenceBlock& block, const std::vector<cv::Mat>& frames, int extent, double full_scale)>;

struct PatternCodec {
  std::string name;                         // the manifest's "type"
  BlockType type = BlockType::kRegistered;  // the built-in rows' own value; kRegistered for added codecs
  CodecRole role = CodecRole::kAbsolute;    // what the block gives the decoder
  std::string help;                         // one line: docs/formats.md and `ramtk patterns --help`
  std::string spec_name;                    // its name in a sequence spec (sequence_spec.h); "" = `name`
  std::vector<CodecParameter> parameters;   // in the order the docs list them
  // Images the block occupies.
  std::function<int(const SequenceBlock& block)> image_count;
  // Ideal projector intensity in [0, 1] of image `image` of the block at projector pixel u along
  // the coded direction (manifest.h's convention), `extent` projector px across.
  std::function<double(const SequenceBlock& block, int image, double u, int extent)> intensity;
  // Checks beyond the parameters' ranges: "" or `key: what is wrong` (may be null).
  std::function<std::string(const SequenceBlock& block, int extent)> check;
  // kOrder codecs: "" or `key: what is wrong` for this block ordering `phase` (may be null).
  std::function<std::string(const SequenceBlock& block, const SequenceBlock& phase)> check_with_phase;
  // kAbsolute codecs the fused decoder does not know: their decode (null for the built-in rows).
  CodecDecodeFunction decode;
};

// Every codec: the built-in rows, then the registered ones in registration order.
std::vector<const PatternCodec*> PatternCodecs();
// The codec of a manifest "type", or nullptr.
const PatternCodec* FindPatternCodec(const std::string& name);
// The codec of a block (its type, or for kRegistered its codec name). InputError if unknown.
const PatternCodec& CodecOf(const SequenceBlock& block);
// Adds a codec (type kRegistered, a decode function for kAbsolute). InputError if the name is taken
// or the row is incomplete. Register before decoding: the table is not guarded against concurrent use.
void RegisterPatternCodec(PatternCodec codec);
// Removes a registered codec; false if there is none of that name (built-in rows stay).
bool UnregisterPatternCodec(const std::string& name);
// A block of the registered codec `codec_name` (its fields at their defaults).
SequenceBlock RegisteredBlock(const std::string& codec_name);

// The codec table as the Markdown rows of docs/formats.md (header included).
std::string PatternCodecTableMarkdown();
// The codec table as text for `ramtk patterns --help`.
std::string PatternCodecHelp();
// The values a parameter accepts, e.g. "integer >= 3", "number in [-360, 360]".
std::string CodecParameterAccepted(const CodecParameter& parameter);

}  // namespace ramtk::vision
