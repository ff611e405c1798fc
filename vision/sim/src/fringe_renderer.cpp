#include "ramtk/vision/sim/fringe_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/gray_code.h"

namespace ramtk::vision {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// One lit sub-ray: what the projector contributes at its hit point.
struct SubSample {
  double albedo = 0.0;  // 0 if the ray hits nothing
  double cosine = 0.0;  // n·l, 0 if unlit (outside the projector image, shadowed or facing away)
  double coord = 0.0;   // fringe coordinate c (projector x or y), valid if cosine > 0
};

// Geometry of one ray: first hit, and whether/where the projector lights it.
struct RayResult {
  bool hit = false;
  int object = -1;
  double depth = 0.0;  // z in the camera frame
  double albedo = 0.0;
  bool lit = false;
  double cosine = 0.0;
  Vec2 projector_pixel = Vec2::Zero();
  Vec2 ideal = Vec2::Zero();  // ideal normalised coordinates of the ray in the camera
};

class RayTracer {
 public:
  RayTracer(const Scene& scene, const PinholeView& camera, const PinholeView& projector, bool shadows)
      : scene_(scene), camera_(camera), projector_(projector), shadows_(shadows) {
    const Isometry3 left_from_camera = camera.view_from_left.inverse();
    camera_centre_ = left_from_camera.translation();
    left_from_camera_rot_ = left_from_camera.linear();
    projector_centre_ = projector.view_from_left.inverse().translation();
  }

  // `initial_ideal`: ideal normalised coordinates of a nearby ray (speeds up undistortion).
  RayResult Trace(const Vec2& pixel, const Vec2& initial_ideal) const {
    RayResult r;
    const Vec3 cam_dir = PixelRay(camera_.intrinsics, pixel, initial_ideal);
    r.ideal = Vec2(cam_dir.x() / cam_dir.z(), cam_dir.y() / cam_dir.z());
    const Vec3 dir = left_from_camera_rot_ * cam_dir;
    const auto hit = IntersectScene(scene_, camera_centre_, dir);
    if (!hit) return r;
    r.hit = true;
    r.object = hit->object;
    r.albedo = hit->albedo;
    r.depth = (camera_.view_from_left * hit->point).z();
    const Vec3 in_projector = projector_.view_from_left * hit->point;
    if (in_projector.z() <= 0.0) return r;
    const Vec2 p = ProjectPoint(projector_.intrinsics, in_projector);
    const CameraIntrinsics& pi = projector_.intrinsics;
    if (p.x() < -0.5 || p.y() < -0.5 || p.x() > pi.width - 0.5 || p.y() > pi.height - 0.5) return r;
    Vec3 to_projector = projector_centre_ - hit->point;
    const double distance = to_projector.norm();
    to_projector /= distance;
    const double cosine = hit->normal.dot(to_projector);
    if (cosine <= 0.0) return r;
    // Shadow ray; the start offset (1e-6 of the distance) keeps it off its own surface.
    if (shadows_ && IsOccluded(scene_, hit->point, to_projector, 1e-6 * distance, distance)) return r;
    r.lit = true;
    r.cosine = cosine;
    r.projector_pixel = p;
    return r;
  }

 private:
  const Scene& scene_;
  const PinholeView& camera_;
  const PinholeView& projector_;
  bool shadows_;
  Vec3 camera_centre_;
  Mat3 left_from_camera_rot_;
  Vec3 projector_centre_;
};

// Bit `shift` of the Gray code at coordinate c seen through a Gaussian projector blur of σ
// projector px across the fringes: each step of the sharp bit pattern becomes the normal CDF.
double BlurredGrayBit(double c, double extent, int bits, int shift, double sigma) {
  const long long sections = 1LL << bits;
  const double cell = extent / static_cast<double>(sections);
  const auto bit = [&](long long n) {
    n = std::max(0LL, std::min(n, sections - 1));
    return static_cast<int>((GrayCodeWord(n) >> shift) & 1);
  };
  const long long c0 = static_cast<long long>(std::floor(c / cell));
  const long long span = 1 + static_cast<long long>(std::ceil(6.0 * sigma / cell));
  double value = bit(c0 - span);
  for (long long n = c0 - span + 1; n <= c0 + span; ++n) {
    const int jump = bit(n) - bit(n - 1);
    if (jump != 0) value += jump * 0.5 * std::erfc(-(c - n * cell) / (std::sqrt(2.0) * sigma));
  }
  return value;
}

}  // namespace

std::vector<PatternFrame> ExpandSequence(const std::vector<SequenceBlock>& blocks) {
  std::vector<PatternFrame> frames;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const SequenceBlock& block = blocks[b];
    const std::string field = "sequence[" + std::to_string(b) + "]";
    if (block.type == BlockType::kRegistered) {  // drawn by its codec (codec.h), sample by sample
      const PatternCodec& codec = CodecOf(block);
      for (int i = 0; i < codec.image_count(block); ++i) {
        PatternFrame f;
        f.type = BlockType::kRegistered;
        f.block = static_cast<int>(b);
        f.index = i;
        f.codec = &codec;
        f.source = block;
        frames.push_back(f);
      }
    } else if (block.type != BlockType::kGrayCode) {
      if (block.steps < 3) throw InputError({"", 0, field + ".steps"}, "a phase shift needs at least 3 steps");
      const bool heterodyne = block.type == BlockType::kHeterodyne;
      const std::vector<double>& all_cycles = block.cycles;
      if (heterodyne && all_cycles.size() < 2)
        throw InputError({"", 0, field + ".cycles"}, "a heterodyne block needs at least 2 frequencies");
      if (!heterodyne && all_cycles.size() != 1)
        throw InputError({"", 0, field + ".cycles"}, "a phase-shift block has one frequency");
      for (double cycles : all_cycles) {
        if (!(cycles > 0.0)) throw InputError({"", 0, field + ".cycles"}, "cycles must be positive");
        for (int k = 0; k < block.steps; ++k) {
          PatternFrame f;
          f.type = BlockType::kPhaseShift;
          f.block = static_cast<int>(b);
          f.index = k;
          f.steps = block.steps;
          f.cycles = cycles;
          f.phase_at_origin_rad = block.phase_at_origin_rad;
          frames.push_back(f);
        }
      }
    } else {
      if (block.bits < 1 || block.bits > 16) throw InputError({"", 0, field + ".bits"}, "bits must be 1..16");
      for (int i = 0; i < block.bits; ++i) {
        PatternFrame f;
        f.type = block.type;
        f.block = static_cast<int>(b);
        f.index = i;
        f.bits = block.bits;
        frames.push_back(f);
      }
    }
  }
  return frames;
}

namespace {

// CDF of box(fill)⊗N(0, σ²) at x: (σ/f)·[G((x + f/2)/σ) − G((x − f/2)/σ)], G(z) = zΦ(z) + φ(z).
double KernelCdf(double fill, double sigma, double x) {
  auto phi_cdf = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  if (fill <= 0.0) return phi_cdf(x / sigma);
  auto g = [&](double z) { return z * phi_cdf(z) + std::exp(-0.5 * z * z) / std::sqrt(kTwoPi); };
  return sigma / fill * (g((x + 0.5 * fill) / sigma) - g((x - 0.5 * fill) / sigma));
}

}  // namespace

std::vector<double> KernelNodeOffsets(const camera::SamplingKernel& kernel, int n) {
  std::vector<double> off(static_cast<std::size_t>(n), 0.0);
  if (n == 1) return off;
  const double f = kernel.fill_factor, sigma = kernel.psf_sigma_px;
  if (sigma <= 0.0) {
    for (int j = 0; j < n; ++j) off[j] = f * ((j + 0.5) / n - 0.5);
    return off;
  }
  const double reach = 0.5 * f + 9.0 * sigma;
  double var = 0.0;
  for (int j = 0; j < n; ++j) {
    const double q = (j + 0.5) / n;
    double lo = -reach, hi = reach;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (KernelCdf(f, sigma, mid) < q ? lo : hi) = mid;
    }
    off[j] = 0.5 * (lo + hi);
    var += off[j] * off[j] / n;
  }
  const double scale = var > 0.0 ? std::sqrt(kernel.VariancePx2() / var) : 1.0;
  for (double& o : off) o *= scale;
  return off;
}

std::string RenderOptions::Validate() const {
  if (supersampling < 1 || supersampling > 16) return "supersampling: must be in 1..16";
  if (const std::string e = kernel.Validate(); !e.empty()) return "kernel." + e;
  if (!(ambient >= 0.0 && std::isfinite(ambient))) return "ambient: must be >= 0";
  if (!(projector_gamma > 0.0 && std::isfinite(projector_gamma))) return "projector_gamma: must be > 0";
  if (!(projector_blur_px >= 0.0 && projector_blur_px < 100.0)) return "projector_blur_px: must be in [0, 100)";
  return "";
}

RenderedView RenderView(const Scene& scene, const PinholeView& camera, const PinholeView& projector,
                        const std::vector<PatternFrame>& frames, const RenderOptions& options) {
  ThrowIfInvalid(options.Validate(), "RenderOptions");
  const int width = camera.intrinsics.width, height = camera.intrinsics.height;
  if (width <= 0 || height <= 0) throw InputError({"", 0, "camera.width"}, "camera image size must be positive");
  const int n = options.supersampling;
  const int samples = n * n;
  // The box pixel keeps its regular grid's own expression (u − ½ + (j + ½)/n).
  const bool box_pixel = options.kernel == camera::SamplingKernel{};
  const std::vector<double> node = KernelNodeOffsets(options.kernel, n);
  const bool vertical = options.direction == FringeDirection::kVertical;
  const double extent = vertical ? projector.intrinsics.width : projector.intrinsics.height;
  const double nan = std::numeric_limits<double>::quiet_NaN();

  RenderedView out;
  for (std::size_t f = 0; f < frames.size(); ++f) out.radiance.emplace_back(height, width, CV_32F);
  out.projector_x.create(height, width, CV_32F);
  out.projector_y.create(height, width, CV_32F);
  out.depth.create(height, width, CV_32F);
  out.object_id.create(height, width, CV_32S);
  out.lit_fraction.create(height, width, CV_32F);

  const RayTracer tracer(scene, camera, projector, options.shadows);
  std::atomic<std::size_t> rows_done{0};
  std::atomic<bool> cancel{false};
  std::mutex progress_mutex;

  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& range) {
    std::vector<SubSample> sub(samples);
    std::vector<double> cos_phi(samples), sin_phi(samples);
    std::vector<long long> gray(samples);
    for (int v = range.begin(); v != range.end(); ++v) {
      if (cancel.load(std::memory_order_relaxed)) return;
      Vec2 previous_ideal((0 - camera.intrinsics.cx) / camera.intrinsics.fx,
                          (v - camera.intrinsics.cy) / camera.intrinsics.fy);
      for (int u = 0; u < width; ++u) {
        // Ground truth from the pixel-centre ray.
        const CameraIntrinsics& k = camera.intrinsics;
        const RayResult centre = tracer.Trace(Vec2(u, v), previous_ideal);
        previous_ideal = centre.ideal;
        out.depth.at<float>(v, u) = centre.hit ? static_cast<float>(centre.depth) : static_cast<float>(nan);
        out.object_id.at<int>(v, u) = centre.object;
        out.projector_x.at<float>(v, u) = centre.lit ? static_cast<float>(centre.projector_pixel.x()) : NAN;
        out.projector_y.at<float>(v, u) = centre.lit ? static_cast<float>(centre.projector_pixel.y()) : NAN;
        int lit_same = 0;
        double ambient_sum = 0.0;
        for (int i = 0; i < n; ++i) {
          for (int j = 0; j < n; ++j) {
            const Vec2 pixel = box_pixel ? Vec2(u - 0.5 + (j + 0.5) / n, v - 0.5 + (i + 0.5) / n)
                                         : Vec2(u + node[j], v + node[i]);
            // Start from the centre's solution shifted by the sub-pixel offset.
            const Vec2 guess = centre.ideal + Vec2((pixel.x() - u) / k.fx, (pixel.y() - v) / k.fy);
            const RayResult r = tracer.Trace(pixel, guess);
            SubSample& s = sub[i * n + j];
            s.albedo = r.albedo;
            s.cosine = r.lit ? r.cosine : 0.0;
            s.coord = vertical ? r.projector_pixel.x() : r.projector_pixel.y();
            ambient_sum += r.albedo;
            if (r.lit && centre.lit && r.object == centre.object) ++lit_same;
          }
        }
        out.lit_fraction.at<float>(v, u) = static_cast<float>(lit_same) / samples;
        const double ambient_term = options.ambient * ambient_sum;
        // Frames of one block share per-sample work: cos φ and sin φ for phase shifts
        // (cos(φ + δ) = cos φ cos δ − sin φ sin δ), the Gray code word for Gray codes.
        int cached_block = -1;
        double cached_cycles = 0.0;
        for (std::size_t f = 0; f < frames.size(); ++f) {
          const PatternFrame& frame = frames[f];
          const bool phase = frame.type == BlockType::kPhaseShift;
          const bool registered = frame.type == BlockType::kRegistered;
          if (frame.block != cached_block || frame.cycles != cached_cycles) {
            cached_block = frame.block;
            cached_cycles = frame.cycles;
            for (int s = 0; s < samples; ++s) {
              if (phase) {
                const double phi = kTwoPi * frame.cycles * sub[s].coord / extent + frame.phase_at_origin_rad;
                cos_phi[s] = std::cos(phi);
                sin_phi[s] = std::sin(phi);
              } else if (!registered) {
                gray[s] = GrayCodeWord(GrayCodeCell(sub[s].coord, frame.bits, extent));
              }
            }
          }
          const double delta = phase ? kTwoPi * frame.index / frame.steps + frame.shift_error_rad : 0.0;
          const double cos_delta = std::cos(delta), sin_delta = std::sin(delta);
          const int shift = frame.bits - 1 - frame.index;
          // Projector defocus: the fringe's modulation falls by exp(−2π²σ²/P²) (P its period),
          // the code stripes' edges become normal CDFs.
          const double blur = options.projector_blur_px;
          const double period = phase ? extent / frame.cycles : 0.0;
          const double modulation = phase && blur > 0.0 ? std::exp(-0.5 * std::pow(kTwoPi * blur / period, 2)) : 1.0;
          double sum = ambient_term;
          for (int s = 0; s < samples; ++s) {
            if (sub[s].cosine <= 0.0) continue;
            double p = registered   ? frame.codec->intensity(frame.source, frame.index, sub[s].coord,
                                                             static_cast<int>(extent))
                       : phase      ? 0.5 + 0.5 * modulation * (cos_phi[s] * cos_delta - sin_phi[s] * sin_delta)
                       : blur > 0.0 ? BlurredGrayBit(sub[s].coord, extent, frame.bits, shift, blur)
                                    : static_cast<double>((gray[s] >> shift) & 1);
            if (options.projector_gamma != 1.0 && p > 0.0) p = std::pow(p, options.projector_gamma);
            sum += sub[s].albedo * sub[s].cosine * p;
          }
          out.radiance[f].at<float>(v, u) = static_cast<float>(sum / samples);
        }
      }
      const std::size_t done = ++rows_done;
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (!options.progress({"render", done, static_cast<std::size_t>(height)})) cancel = true;
      }
    }
  });
  out.cancelled = cancel.load();
  return out;
}

std::string SensorOptions::Validate() const {
  if (bits != 8 && bits != 10 && bits != 12 && bits != 16) return "bits: must be 8, 10, 12 or 16";
  if (!(exposure > 0.0 && std::isfinite(exposure))) return "exposure: must be > 0";
  if (!(full_well_electrons > 0.0)) return "full_well_electrons: must be > 0";
  if (!(read_noise_electrons >= 0.0)) return "read_noise_electrons: must be >= 0";
  if (!(blur_sigma_px >= 0.0 && blur_sigma_px < 100.0)) return "blur_sigma_px: must be in [0, 100)";
  if (!(soft_knee_fraction == 0.0 || (soft_knee_fraction > 0.0 && soft_knee_fraction < 1.0)))
    return "soft_knee_fraction: must be 0 (linear) or in (0, 1)";
  return "";
}

cv::Mat ApplySensor(const cv::Mat& radiance, double gain, const SensorOptions& o, std::uint64_t seed,
                    std::uint64_t stream) {
  ThrowIfInvalid(o.Validate(), "SensorOptions");
  CV_Assert(radiance.type() == CV_32F);
  const double max_value = o.MaxValue();
  cv::Mat mean;
  radiance.convertTo(mean, CV_32F, o.exposure * gain * max_value);
  if (o.blur_sigma_px > 0.0)
    cv::GaussianBlur(mean, mean, cv::Size(0, 0), o.blur_sigma_px, o.blur_sigma_px, cv::BORDER_REFLECT);
  cv::Mat out(mean.size(), o.bits == 8 ? CV_8U : CV_16U);
  const double dn_per_electron = max_value / o.full_well_electrons;
  const double read_var_dn = std::pow(o.read_noise_electrons * dn_per_electron, 2);
  const double knee = o.soft_knee_fraction * max_value;
  tbb::parallel_for(tbb::blocked_range<int>(0, mean.rows, 16), [&](const tbb::blocked_range<int>& range) {
    for (int v = range.begin(); v != range.end(); ++v) {
      std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                        static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32),
                        static_cast<std::uint32_t>(v)};
      std::mt19937_64 rng(seq);
      std::normal_distribution<double> normal(0.0, 1.0);
      const float* m = mean.ptr<float>(v);
      for (int u = 0; u < mean.cols; ++u) {
        double dn = m[u];
        if (o.noise) {
          const double var = std::max(dn, 0.0) * dn_per_electron + read_var_dn;
          dn += std::sqrt(var) * normal(rng);
        }
        if (knee > 0.0 && dn > knee) {
          const double x = (dn - knee) / (max_value - knee);
          dn = knee + (max_value - knee) * x / std::sqrt(1.0 + x * x);
        }
        const double q = std::min(std::max(std::round(dn), 0.0), max_value);
        if (o.bits == 8) {
          out.ptr<std::uint8_t>(v)[u] = static_cast<std::uint8_t>(q);
        } else {
          out.ptr<std::uint16_t>(v)[u] = static_cast<std::uint16_t>(q);
        }
      }
    }
  });
  return out;
}

}  // namespace ramtk::vision
