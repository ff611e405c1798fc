// Independent fringe-image generator; see fringe_gen.h and README.md.
#include "fringe_gen.h"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace indep {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFullScale = 65535.0;

struct Pinhole {
  double fx, fy, cx, cy;
  int width, height;
};

// The measured surface: a plane through `origin` with normal `n` (axes e1, e2 in the plane) and
// a Gaussian bump of height h and width s; albedo: smooth variation plus dark circular markers.
struct Surface {
  Eigen::Vector3d origin, n, e1, e2;
  double bump_height_mm = 0, bump_sigma_mm = 1;
  Eigen::Vector2d bump_centre{0, 0};
  std::vector<Eigen::Vector3d> markers;  // x, y (plane coordinates, mm), radius mm

  double Height(double x, double y) const {
    const double dx = x - bump_centre.x(), dy = y - bump_centre.y();
    return bump_height_mm * std::exp(-(dx * dx + dy * dy) / (2 * bump_sigma_mm * bump_sigma_mm));
  }
  // Ray from the origin along unit d: the hit point (fixed-point iteration on the height field).
  bool Intersect(const Eigen::Vector3d& d, Eigen::Vector3d* hit, Eigen::Vector2d* plane_xy) const {
    const double nd = n.dot(d);
    if (std::fabs(nd) < 1e-6) return false;
    double t = n.dot(origin) / nd;
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d p = t * d - origin;
      const double h = Height(e1.dot(p), e2.dot(p));
      const double next = (n.dot(origin) + h) / nd;
      if (std::fabs(next - t) < 1e-9) {
        t = next;
        break;
      }
      t = next;
    }
    if (t <= 0) return false;
    *hit = t * d;
    const Eigen::Vector3d p = *hit - origin;
    *plane_xy = Eigen::Vector2d(e1.dot(p), e2.dot(p));
    return true;
  }
  Eigen::Vector3d Normal(double x, double y) const {
    const double eps = 1e-3;
    const double hx = (Height(x + eps, y) - Height(x - eps, y)) / (2 * eps);
    const double hy = (Height(x, y + eps) - Height(x, y - eps)) / (2 * eps);
    return (n - hx * e1 - hy * e2).normalized();
  }
  double Albedo(double x, double y) const {
    double a = 0.75 + 0.1 * std::sin(x / 83.0 + 0.3) * std::cos(y / 67.0 - 0.2);
    for (const auto& m : markers) {
      if ((Eigen::Vector2d(x, y) - m.head<2>()).norm() < m.z()) a = 0.12;  // printed dark target
    }
    return a;
  }
};

// Projector pattern image i (radiance in [0, 1] per projector pixel) before optics.
struct PatternSpec {
  int steps = 8, cycles = 32, bits = 6;
  double phase_at_origin = -M_PI;
};

double PatternValue(const PatternSpec& p, int image, double u, int width, const std::vector<double>& step_error) {
  if (image < p.steps) {
    const double phi = 2 * M_PI * p.cycles * u / width + p.phase_at_origin;
    return 0.5 + 0.5 * std::cos(phi + 2 * M_PI * image / p.steps + step_error[image]);
  }
  const int j = image - p.steps;
  const long cell = static_cast<long>(std::floor(u * (1L << p.bits) / width));
  const long gray = cell ^ (cell >> 1);
  return ((gray >> (p.bits - 1 - j)) & 1L) ? 1.0 : 0.0;
}

double Bilinear(const std::vector<float>& img, int w, int h, double x, double y) {
  if (x < 0 || y < 0 || x > w - 1 || y > h - 1) return 0.0;
  const int x0 = std::min(static_cast<int>(x), w - 2), y0 = std::min(static_cast<int>(y), h - 2);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = &img[static_cast<size_t>(y0) * w];
  const float* r1 = r0 + w;
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

}  // namespace

double SoftKnee(double signal_dn, double knee_dn, double range_dn) {
  if (signal_dn <= knee_dn) return signal_dn;
  const double span = range_dn - knee_dn;
  return knee_dn + span * std::tanh((signal_dn - knee_dn) / span);
}

double SensePixel(const SensorModel& s, double mean_e, Rng& rng) {
  const double photo_e = rng.Poisson(std::max(mean_e, 0.0));
  const double read_e = s.read_noise_e * rng.Normal();
  double signal = s.gain_dn_per_e * (photo_e + read_e);
  if (s.knee_fraction > 0) {  // the pixel compresses its photo-charge; the readout adds its noise after
    const double range = kFullScale - s.black_level_dn;
    signal = SoftKnee(s.gain_dn_per_e * photo_e, s.knee_fraction * range, range) + s.gain_dn_per_e * read_e;
  }
  const double dn = std::round(s.black_level_dn + signal);
  return std::clamp(dn, 0.0, kFullScale);
}

void PillboxBlur(std::vector<float>& image, int width, int height, double radius) {
  if (radius <= 0) return;
  const int r = static_cast<int>(std::ceil(radius));
  const int size = 2 * r + 1;
  std::vector<double> kernel(size * size, 0.0);
  // Area of the disc inside each kernel cell: ∫ over x of the clipped chord, midpoint rule with
  // 256 nodes per cell (area error < 1e-5 pixel).
  const int nodes = 256;
  double total = 0;
  for (int ky = -r; ky <= r; ++ky) {
    for (int kx = -r; kx <= r; ++kx) {
      double area = 0;
      for (int i = 0; i < nodes; ++i) {
        const double x = kx - 0.5 + (i + 0.5) / nodes;
        if (std::fabs(x) >= radius) continue;
        const double half = std::sqrt(radius * radius - x * x);
        area += std::max(0.0, std::min(half, ky + 0.5) - std::max(-half, ky - 0.5)) / nodes;
      }
      kernel[(ky + r) * size + kx + r] = area;
      total += area;
    }
  }
  for (double& k : kernel) k /= total;
  std::vector<float> out(image.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double acc = 0;
      for (int ky = -r; ky <= r; ++ky) {
        const int yy = std::clamp(y + ky, 0, height - 1);
        for (int kx = -r; kx <= r; ++kx) {
          const double k = kernel[(ky + r) * size + kx + r];
          if (k == 0) continue;
          acc += k * image[static_cast<size_t>(yy) * width + std::clamp(x + kx, 0, width - 1)];
        }
      }
      out[static_cast<size_t>(y) * width + x] = static_cast<float>(acc);
    }
  }
  image.swap(out);
}

void GenerateFringe(const GenOptions& o) {
  const std::string& effect = o.effect;
  if (effect != "none" && effect != "camera_defocus" && effect != "soft_knee_response" &&
      effect != "projector_nonlinearity" && effect != "phase_shift_error" && effect != "defocus") {
    throw std::runtime_error("fringe: unknown effect '" + effect + "'");
  }
  Rng rng(0x51ed270b27a1c3d5ULL ^ (static_cast<std::uint64_t>(o.seed) * 2654435761ULL + 3));
  const double mag = o.magnitude;

  // Camera: 640×512, 1400 px focal length (an 8 mm lens on 5.5 µm pixels), at the origin looking along +z. Projector: 1280×800 DLP-class, 200 mm to the right, toed in to
  // the working point at 700 mm.
  const Pinhole cam{1400, 1400, 319.5 + rng.Uniform(-3, 3), 255.5 + rng.Uniform(-3, 3), 640, 512};
  const Pinhole proj{1800, 1800, 639.5, 399.5, 1280, 800};
  const double work_mm = 700 + rng.Uniform(-30, 30);
  const Eigen::Vector3d proj_centre(200 + rng.Uniform(-10, 10), rng.Uniform(-10, 10), 0);
  const Eigen::Vector3d proj_look = (Eigen::Vector3d(0, 0, work_mm) - proj_centre).normalized();
  const Eigen::Vector3d proj_x = Eigen::Vector3d::UnitY().cross(proj_look).normalized();
  const Eigen::Vector3d proj_y = proj_look.cross(proj_x);
  Eigen::Matrix3d proj_from_cam_rot;
  proj_from_cam_rot.row(0) = proj_x.transpose();
  proj_from_cam_rot.row(1) = proj_y.transpose();
  proj_from_cam_rot.row(2) = proj_look.transpose();

  Surface surface;
  surface.origin = Eigen::Vector3d(0, 0, work_mm);
  const double tilt = rng.Uniform(5, 25) * kDeg, tilt_dir = rng.Uniform(-M_PI, M_PI);
  surface.n = Eigen::Vector3d(std::sin(tilt) * std::cos(tilt_dir), std::sin(tilt) * std::sin(tilt_dir), -std::cos(tilt));
  surface.e1 = surface.n.unitOrthogonal();
  surface.e2 = surface.n.cross(surface.e1);
  surface.bump_height_mm = rng.Uniform(10, 30) * (rng.Uniform() < 0.5 ? -1 : 1);
  surface.bump_sigma_mm = rng.Uniform(40, 80);
  surface.bump_centre = Eigen::Vector2d(rng.Uniform(-60, 60), rng.Uniform(-40, 40));
  for (int i = 0; i < 12; ++i) {
    surface.markers.emplace_back(rng.Uniform(-150, 150), rng.Uniform(-120, 120), rng.Uniform(3, 6));
  }

  PatternSpec spec;
  const int num_images = spec.steps + spec.bits;
  std::vector<double> step_error(spec.steps, 0.0);
  SensorModel sensor;
  sensor.gain_dn_per_e = o.gain;
  double gamma = 1.0, camera_blur_px = 0, projector_blur_px = 0;

  Truth truth;
  truth.kind = "fringe";
  truth.effect = effect;
  truth.expected = effect;
  truth.accepted = {effect};
  nlohmann::json& par = truth.parameters;
  if (effect == "camera_defocus") {
    camera_blur_px = std::isnan(mag) ? 1.5 : mag;
    par["camera_blur_radius_px"] = camera_blur_px;
  } else if (effect == "defocus") {
    projector_blur_px = std::isnan(mag) ? 3.0 : mag;
    par["projector_blur_radius_px"] = projector_blur_px;
  } else if (effect == "soft_knee_response") {
    sensor.knee_fraction = std::isnan(mag) ? 0.6 : mag;
    par["knee_fraction_of_full_scale"] = sensor.knee_fraction;
  } else if (effect == "projector_nonlinearity") {
    gamma = std::isnan(mag) ? 2.2 : mag;
    par["projector_gamma"] = gamma;
  } else if (effect == "phase_shift_error") {
    const double sigma = (std::isnan(mag) ? 2.0 : mag) * kDeg;
    std::vector<double> deg;
    for (int k = 1; k < spec.steps; ++k) step_error[k] = sigma * rng.Normal();  // step 0 is the reference
    for (double e : step_error) deg.push_back(e / kDeg);
    par["step_error_deg"] = deg;
    par["step_error_sigma_deg"] = sigma / kDeg;
  }

  // Projector images: the pattern per projector pixel, its response (gamma), optical blur.
  std::vector<std::vector<float>> projector(num_images);
  for (int i = 0; i < num_images; ++i) {
    projector[i].resize(static_cast<size_t>(proj.width) * proj.height);
    std::vector<float> row(proj.width);
    for (int u = 0; u < proj.width; ++u) {
      // Continuous levels: an 8-bit DLP's quantisation (≈ 0.1 % of B) is left out so that `none`
      // holds camera noise only.
      const double level = PatternValue(spec, i, u, proj.width, step_error);
      row[u] = static_cast<float>(std::pow(level, gamma));
    }
    for (int v = 0; v < proj.height; ++v) std::copy(row.begin(), row.end(), projector[i].begin() + static_cast<long>(v) * proj.width);
    PillboxBlur(projector[i], proj.width, proj.height, projector_blur_px);
  }

  // Geometry per camera pixel, sub×sub rays (2×2 by default: a pixel integrates its area; 1: the
  // centre ray alone, point sampling): projector coordinate and the radiometric weight (albedo ×
  // projector irradiance × cos falloff).
  const int w = cam.width, h = cam.height, sub = o.sub;
  const size_t npix = static_cast<size_t>(w) * h;
  std::vector<Eigen::Vector2f> proj_uv(npix * sub * sub);
  std::vector<float> weight(npix * sub * sub), ambient(npix, 0.0f);
  const double ambient_level = 0.03;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int s = 0; s < sub * sub; ++s) {
        const double px = x - 0.5 + (s % sub + 0.5) / sub, py = y - 0.5 + (s / sub + 0.5) / sub;
        const Eigen::Vector3d d = Eigen::Vector3d((px - cam.cx) / cam.fx, (py - cam.cy) / cam.fy, 1).normalized();
        const size_t k = (static_cast<size_t>(y) * w + x) * sub * sub + s;
        Eigen::Vector3d hit;
        Eigen::Vector2d xy;
        proj_uv[k] = Eigen::Vector2f(-1, -1);
        weight[k] = 0;
        if (!surface.Intersect(d, &hit, &xy)) continue;
        const Eigen::Vector3d normal = surface.Normal(xy.x(), xy.y());
        const Eigen::Vector3d in_proj = proj_from_cam_rot * (hit - proj_centre);
        if (in_proj.z() <= 0) continue;
        const Eigen::Vector3d to_proj = (proj_centre - hit).normalized();
        const double cos_in = std::fabs(normal.dot(to_proj));  // projector irradiance ∝ cos(incidence)/r²
        const double dist2 = (proj_centre - hit).squaredNorm() / (work_mm * work_mm);
        const double albedo = surface.Albedo(xy.x(), xy.y());    // Lambertian: radiance independent of view
        const double vignette = std::pow(d.z(), 4);              // cos⁴ law of the camera lens
        proj_uv[k] = Eigen::Vector2f(static_cast<float>(proj.fx * in_proj.x() / in_proj.z() + proj.cx),
                                     static_cast<float>(proj.fy * in_proj.y() / in_proj.z() + proj.cy));
        weight[k] = static_cast<float>(albedo * cos_in / dist2 * vignette / (sub * sub));
        ambient[static_cast<size_t>(y) * w + x] += static_cast<float>(albedo * ambient_level * vignette / (sub * sub));
      }
    }
  }
  // Exposure: the brightest lit pixel at white reaches 85 % of the full scale (pre-compression).
  double peak = 0;
  for (size_t p = 0; p < npix; ++p) {
    double sum = ambient[p];
    for (int s = 0; s < sub * sub; ++s) sum += weight[p * sub * sub + s];
    peak = std::max(peak, sum);
  }
  const double full_well_e = (kFullScale - sensor.black_level_dn) / sensor.gain_dn_per_e;
  const double exposure_e = 0.85 * full_well_e / peak;
  // Photo-response non-uniformity: 0.5 % per-pixel gain, fixed for the sensor.
  std::vector<float> prnu(npix);
  for (auto& v : prnu) v = static_cast<float>(1.0 + 0.005 * rng.Normal());

  const std::filesystem::path out(o.out_dir);
  std::filesystem::create_directories(out / "left");
  nlohmann::json files = nlohmann::json::array();
  std::vector<float> mean_e(npix);
  for (int i = 0; i < num_images; ++i) {
    for (size_t p = 0; p < npix; ++p) {
      double e = ambient[p];
      for (int s = 0; s < sub * sub; ++s) {
        const size_t k = p * sub * sub + s;
        if (weight[k] > 0) e += weight[k] * Bilinear(projector[i], proj.width, proj.height, proj_uv[k].x(), proj_uv[k].y());
      }
      mean_e[p] = static_cast<float>(e * exposure_e);
    }
    PillboxBlur(mean_e, w, h, camera_blur_px);  // optics first: the defocus disc blurs the irradiance,
    for (size_t p = 0; p < npix; ++p) mean_e[p] *= prnu[p];  // then each pixel's own response
    cv::Mat img(h, w, CV_16UC1);
    for (int y = 0; y < h; ++y) {
      auto* row = img.ptr<std::uint16_t>(y);
      for (int x = 0; x < w; ++x) row[x] = static_cast<std::uint16_t>(SensePixel(sensor, mean_e[static_cast<size_t>(y) * w + x], rng));
    }
    char name[32];
    std::snprintf(name, sizeof name, "left/%02d.png", i);
    const std::string tmp = (out / (std::string(name) + ".tmp.png")).string();
    if (!cv::imwrite(tmp, img)) throw std::runtime_error("cannot write " + tmp);
    std::filesystem::rename(tmp, out / name);
    files.push_back(name);
  }

  nlohmann::json m;
  m["format"] = "ramtk-fringe-set";
  m["version"] = 1;
  m["projector"] = {{"width", proj.width}, {"height", proj.height}};
  m["direction"] = "vertical";
  m["sequence"] = {{{"type", "phase_shift"}, {"steps", spec.steps}, {"cycles", spec.cycles}, {"phase_at_origin_deg", -180.0}},
                   {{"type", "gray_code"}, {"bits", spec.bits}, {"complementary", true}}};
  m["cameras"] = {{"left", files}};
  m["bit_depth"] = 16;
  m["generator"] = "ramtk_indep_gen (independent, tests/independent)";
  WriteFileAtomic((out / "manifest.json").string(), m.dump(2) + "\n");

  par["camera_gain_dn_per_e"] = sensor.gain_dn_per_e;
  par["read_noise_e"] = sensor.read_noise_e;
  par["black_level_dn"] = sensor.black_level_dn;
  par["full_well_e"] = full_well_e;
  par["peak_signal_e"] = 0.85 * full_well_e;
  par["prnu"] = 0.005;
  par["ambient_fraction"] = ambient_level;
  par["projector_levels"] = "continuous";
  par["image_size"] = {w, h};
  par["working_distance_mm"] = work_mm;
  par["surface_tilt_deg"] = tilt / kDeg;
  par["bump_height_mm"] = surface.bump_height_mm;
  WriteTruth(o.out_dir, truth, o);
}

}  // namespace indep
