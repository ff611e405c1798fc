// Pattern generation: every block drawn by its codec (codec.h), one line along the coded direction
// expanded to the projector image.
#include "ramtk/vision/fringe/patterns.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/provenance.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/image_io.h"

namespace ramtk::vision {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// One row of values along the coded direction, expanded to the projector image.
cv::Mat Expand(const std::vector<float>& line, const FringeManifest& m) {
  cv::Mat img(m.projector_height, m.projector_width, CV_32FC1);
  for (int y = 0; y < img.rows; ++y) {
    float* row = img.ptr<float>(y);
    for (int x = 0; x < img.cols; ++x) row[x] = m.direction == FringeDirection::kVertical ? line[x] : line[y];
  }
  return img;
}

}  // namespace

double PatternPhase(double u, double cycles, int extent, double phase_at_origin_rad) {
  return kTwoPi * cycles * u / extent + phase_at_origin_rad;
}

std::vector<cv::Mat> GeneratePatterns(const FringeManifest& m) {
  const int extent = m.Extent();
  std::vector<cv::Mat> out;
  std::vector<float> line(extent);
  for (const SequenceBlock& b : m.sequence) {
    const PatternCodec& codec = CodecOf(b);
    for (int i = 0; i < codec.image_count(b); ++i) {
      for (int u = 0; u < extent; ++u) line[u] = static_cast<float>(codec.intensity(b, i, u, extent));
      out.push_back(Expand(line, m));
    }
  }
  return out;
}

std::vector<cv::Mat> QuantisePatterns(const std::vector<cv::Mat>& patterns, int bits) {
  if (bits != 8 && bits != 16) throw InputError({"", 0, "--bits"}, "expected 8 or 16, got " + std::to_string(bits));
  const double full = bits == 8 ? 255.0 : 65535.0;
  std::vector<cv::Mat> out;
  for (const cv::Mat& p : patterns) {
    cv::Mat q;
    p.convertTo(q, bits == 8 ? CV_8U : CV_16U, full);  // rounds to nearest and saturates
    out.push_back(q);
  }
  return out;
}

void WritePatternSet(const std::string& out_dir, FringeManifest manifest, int bits, bool overwrite,
                     const Provenance* provenance) {
  manifest.cameras.clear();
  std::vector<std::string> names;
  for (int i = 0; i < manifest.ImageCount(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "pattern_%02d.png", i);
    names.push_back(name);
  }
  manifest.cameras["projector"] = names;
  manifest.path.clear();
  manifest.Check();
  const std::vector<cv::Mat> images = QuantisePatterns(GeneratePatterns(manifest), bits);
  StagedFolder staged(out_dir, overwrite, "--out");
  for (std::size_t i = 0; i < images.size(); ++i) WriteImage((staged.path() / names[i]).string(), images[i]);
  WriteFringeManifest((staged.path() / "manifest.json").string(), manifest);
  if (provenance) WriteFolderProvenance(staged.path().string(), *provenance);
  staged.Commit();
}

}  // namespace ramtk::vision
