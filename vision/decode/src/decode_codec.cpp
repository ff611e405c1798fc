// The decode of a codec that brings its own (codec.h PatternCodec::decode): the codec turns the
// frames into a coordinate, a modulation and a sigma; this file makes the mask and the summary.
#include <algorithm>
#include <cmath>
#include <limits>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/fringe/codec.h"

namespace ramtk::vision::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Throws InputError unless `m` is a CV_32F map of `size`.
void RequireMap(const cv::Mat& m, const cv::Size& size, const std::string& codec, const char* what) {
  if (m.type() != CV_32F || m.size() != size)
    throw InputError({"", 0, "codec " + codec},
                     std::string("its decode must return a CV_32F ") + what + " map of the images' size");
}

float Median(std::vector<float>& v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

DecodedCamera DecodeFramesWithCodec(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                                    const DecodeOptions& options, const std::string& camera) {
  const SequenceBlock& block = m.sequence.at(0);
  const PatternCodec& codec = CodecOf(block);
  std::vector<cv::Mat> as_float(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].convertTo(as_float[i], CV_32F);
  CodecDecodeResult r = codec.decode(block, as_float, m.Extent(), full_scale);
  const cv::Size size = frames[0].size();
  RequireMap(r.coordinate, size, codec.name, "coordinate");
  RequireMap(r.modulation, size, codec.name, "modulation");
  RequireMap(r.sigma_coordinate, size, codec.name, "sigma_coordinate");

  DecodedCamera out;
  DecodeSummary& sum = out.summary;
  sum.camera = camera;
  sum.width = size.width;
  sum.height = size.height;
  sum.steps = block.ImageCount();
  sum.period_px = m.Extent();  // one "period" across the projector: the coordinate is absolute
  sum.gamma_from_harmonics = std::numeric_limits<double>::quiet_NaN();
  const double to_rad = 2 * CV_PI / sum.period_px;
  const float b_min = static_cast<float>(options.min_modulation_fraction * full_scale);
  sum.modulation_rule = "fixed";  // the codec reports no sigma_I: its pixels keep the fixed threshold
  sum.modulation_threshold_dn = b_min;
  out.mask.create(size, CV_8U);
  out.sigma_phase.create(size, CV_32F);
  std::vector<float> modulation, sigma;
  for (int y = 0; y < size.height; ++y) {
    float* c = r.coordinate.ptr<float>(y);
    const float* b = r.modulation.ptr<float>(y);
    float* sc = r.sigma_coordinate.ptr<float>(y);
    float* sp = out.sigma_phase.ptr<float>(y);
    uchar* mk = out.mask.ptr<uchar>(y);
    for (int x = 0; x < size.width; ++x) {
      const bool low = !(b[x] >= b_min);
      const bool decoded = std::isfinite(c[x]) && std::isfinite(sc[x]);
      mk[x] = !low && decoded ? 255 : 0;
      if (!mk[x]) {
        low ? ++sum.low_modulation : ++sum.unwrap_rejected;
        c[x] = sc[x] = sp[x] = kNaN;
        continue;
      }
      sp[x] = static_cast<float>(sc[x] * to_rad);
      modulation.push_back(b[x]);
      sigma.push_back(sp[x]);
    }
  }
  sum.valid_pixels = static_cast<long>(modulation.size());
  sum.valid_fraction = static_cast<double>(sum.valid_pixels) / out.mask.total();
  sum.outliers = static_cast<long>(out.mask.total()) - sum.valid_pixels;
  sum.median_modulation_dn = Median(modulation);
  sum.median_sigma_phase_rad = Median(sigma);
  out.coordinate = r.coordinate;
  out.modulation = r.modulation;
  out.sigma_coordinate = r.sigma_coordinate;
  out.wrapped = r.coordinate * to_rad;
  out.background = cv::Mat::zeros(size, CV_32F);
  out.fit_residual = cv::Mat::zeros(size, CV_32F);
  if (options.progress) options.progress(Progress{"done", 4, 4});
  return out;
}

}  // namespace ramtk::vision::detail
