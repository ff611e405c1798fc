#include "ramtk/vision/sim/fringe_simulator.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/provenance.h"
#include "ramtk/core/units.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/sim/truth_json.h"

namespace ramtk::vision {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// view_from_left of a camera at `centre` looking at `target`, image y pointing along +y ("down").
Isometry3 LookAt(const Vec3& centre, const Vec3& target) {
  const Vec3 z = (target - centre).normalized();
  const Vec3 x = Vec3::UnitY().cross(z).normalized();
  const Vec3 y = z.cross(x);
  Mat3 r;
  r.row(0) = x;
  r.row(1) = y;
  r.row(2) = z;
  Isometry3 view_from_left = Isometry3::Identity();
  view_from_left.linear() = r;
  view_from_left.translation() = -r * centre;
  return view_from_left;
}

json Vec3Json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

json SequenceJson(const std::vector<SequenceBlock>& blocks) {
  json seq = json::array();
  for (const SequenceBlock& b : blocks) {
    if (b.type == BlockType::kHeterodyne) {
      seq.push_back({{"type", "heterodyne"},
                     {"steps", b.steps},
                     {"cycles", b.cycles},
                     {"phase_at_origin_deg", RadToDeg(b.phase_at_origin_rad)}});
    } else if (b.type == BlockType::kPhaseShift) {
      seq.push_back({{"type", "phase_shift"},
                     {"steps", b.steps},
                     {"cycles", b.cycles.at(0)},
                     {"phase_at_origin_deg", RadToDeg(b.phase_at_origin_rad)}});
    } else if (b.type == BlockType::kRegistered) {
      seq.push_back({{"type", b.codec}});
    } else {
      seq.push_back({{"type", "gray_code"}, {"bits", b.bits}, {"complementary", b.complementary}});
    }
  }
  return seq;
}

// Float truth maps (projector coordinate, lit fraction) as 32-bit float TIFF (image_io.h).
void WriteFloatTiff(const std::string& path, const cv::Mat& image) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  WriteImage(path, f);
}

// Writes an 8-bit image as is; a 10/12/16-bit one as 16-bit PNG scaled to 16-bit full scale
// (q·65535 / (2^bits − 1), rounded), so 16-bit readers see saturation at 65535.
void WritePng(const std::string& path, const cv::Mat& image, int bits) {
  cv::Mat out = image;
  if (bits > 8 && bits < 16) {
    out = cv::Mat(image.size(), CV_16U);
    const double scale = 65535.0 / ((1 << bits) - 1);
    for (int v = 0; v < image.rows; ++v)
      for (int u = 0; u < image.cols; ++u)
        out.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(image.at<std::uint16_t>(v, u) * scale));
  }
  WriteImage(path, out);
}

std::string FrameName(int i, const std::string& format) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "%02d.", i);
  return buf + format;
}

}  // namespace

std::vector<std::string> FringeEffects::Names() {
  return {
#define RAMTK_FRINGE_EFFECT(name, off, unit, help) #name,
#include "ramtk/vision/sim/fringe_effects.def"
  };
}

std::string FringeEffects::Help() {
  std::string s;
#define RAMTK_FRINGE_EFFECT(name, off, unit, help) s += std::string(s.empty() ? "" : ", ") + #name + " (" + unit + ")";
#include "ramtk/vision/sim/fringe_effects.def"
  return s;
}

void FringeEffects::Set(const std::string& name, double m, const std::string& where) {
  if (!std::isfinite(m)) throw InputError({"", 0, where}, "effect " + name + ": magnitude must be finite");
  double* field = nullptr;
#define RAMTK_FRINGE_EFFECT(row, off, unit, help) \
  if (name == #row) field = &row;
#include "ramtk/vision/sim/fringe_effects.def"
  if (!field) throw InputError({"", 0, where}, "unknown effect '" + name + "' (known: " + Help() + ")");
  *field = m;
  if (const std::string p = Validate(); !p.empty()) throw InputError({"", 0, where}, SplitOptionsProblem(p).message);
}

std::map<std::string, double> FringeEffects::ByName() const {
  return {
#define RAMTK_FRINGE_EFFECT(name, off, unit, help) {#name, name},
#include "ramtk/vision/sim/fringe_effects.def"
  };
}

std::string FringeEffects::Validate() const {
  std::string problem;  // the first one
  auto CheckMagnitude = [&problem](bool ok, const std::string& where, const std::string& name,
                                   const std::string& rule) {
    if (!ok && problem.empty()) problem = where + ": effect " + name + ": magnitude " + rule;
  };
  const std::string w = "effects";
  CheckMagnitude(projector_nonlinearity > 0.0 && projector_nonlinearity <= 10.0, w, "projector_nonlinearity",
                 "(gamma) must be in (0, 10]");
  CheckMagnitude(phase_shift_error >= 0.0 && phase_shift_error <= 90.0, w, "phase_shift_error",
                 "(degrees) must be in [0, 90]");
  CheckMagnitude(intensity_drift > -1.0 && intensity_drift <= 10.0, w, "intensity_drift", "must be in (-1, 10]");
  CheckMagnitude(saturation > 0.0 && saturation <= 100.0, w, "saturation", "(exposure factor) must be in (0, 100]");
  CheckMagnitude(defocus >= 0.0 && defocus < 100.0, w, "defocus", "(blur sigma, px) must be in [0, 100)");
  CheckMagnitude(camera_defocus >= 0.0 && camera_defocus < 100.0, w, "camera_defocus",
                 "(blur sigma, px) must be in [0, 100)");
  CheckMagnitude(soft_knee_response == 0.0 || (soft_knee_response > 0.0 && soft_knee_response < 1.0), w,
                 "soft_knee_response", "(knee, fraction of full scale) must be 0 (off) or in (0, 1)");
  CheckMagnitude(ambient_light >= 0.0 && ambient_light <= 100.0, w, "ambient_light", "must be in [0, 100]");
  CheckMagnitude(std::abs(lens_distortion_unmodelled) <= 1.0, w, "lens_distortion_unmodelled",
                 "(extra k1) must be in [-1, 1]");
  return problem;
}

std::string FringeSimulationConfig::Validate() const {
  if (std::string p = effects.Validate(); !p.empty()) return p;  // its fields are named effects*
  if (std::string p = sensor.Validate(); !p.empty()) return "sensor." + p;
  RenderOptions ro;
  ro.supersampling = supersampling;
  if (std::string p = ro.Validate(); !p.empty()) return p;
  for (const CameraIntrinsics* c : {&cameras.left, &cameras.right}) {
    if (!c->sampling_kernel) continue;
    if (std::string p = c->sampling_kernel->Validate(); !p.empty()) return "cameras.sampling_kernel." + p;
    if (supersampling == 1 && !(*c->sampling_kernel == camera::SamplingKernel{0.0, 0.0}))
      return "supersampling: 1 ray per pixel samples a point; a stated kernel with a fill factor or a PSF needs "
             "supersampling >= 2";
  }
  try {
    ExpandSequence(sequence);
  } catch (const InputError& e) {
    return "sequence: " + e.message();
  }
  if (sequence.empty()) return "sequence: the pattern sequence is empty";
  if (frame_format != "png" && frame_format != "bmp") return "frame_format: must be png or bmp, got " + frame_format;
  if (frame_format == "bmp" && sensor.bits != 8)
    return "frame_format: bmp holds 8-bit frames; the sensor has " + std::to_string(sensor.bits) + " bits (use png)";
  for (const CameraIntrinsics* c : {&cameras.left, &cameras.right, &projector.intrinsics})
    if (c->width <= 0 || c->height <= 0 || !(c->fx > 0) || !(c->fy > 0))
      return "cameras: image sizes and focal lengths must be positive";
  if (scene.ObjectCount() == 0) return "scene: the scene is empty";
  for (const Sphere& s : scene.spheres)
    if (!(s.radius > 0.0)) return "scene.spheres: sphere radius must be positive";
  return "";
}

FringeSimulationConfig ScaleCameraWindows(FringeSimulationConfig c, double scale) {
  for (CameraIntrinsics* cam : {&c.cameras.left, &c.cameras.right}) {
    cam->fx *= scale;
    cam->fy *= scale;
    cam->cx = (cam->cx + 0.5) * scale - 0.5;
    cam->cy = (cam->cy + 0.5) * scale - 0.5;
    cam->width = static_cast<int>(std::lround(cam->width * scale));
    cam->height = static_cast<int>(std::lround(cam->height * scale));
  }
  return c;
}

FringeSimulationConfig MakeFringePreset(const std::string& name) {
  return MakeFringePreset(name, Vec3(0.0, 0.0, 700.0));
}

FringeSimulationConfig MakeFringePreset(const std::string& name, const Vec3& ball_in_left) {
  if (name != "thesis" && name != "small")
    throw InputError({"", 0, "--preset"}, "unknown preset '" + name + "' (known: thesis, small)");
  FringeSimulationConfig c;
  c.preset = name;
  // The rig is aimed at (0, 0, 700); the ball may sit elsewhere in the field.
  const Vec3 aim(0.0, 0.0, 700.0);
  const Vec3 ball = ball_in_left;
  // Cameras as in thesis §5.1 (IMPERX B3320M, 3312×2488, 5.5 µm pixels, ZEISS 25 mm lenses):
  // focused at 700 mm the image distance is 25.9 mm, f = 4700 px, a 493 × 370 mm field per camera
  // (the thesis quotes ~570 × 430 mm for the pair). Distortion ~0.5 % in the corners.
  CameraIntrinsics left{4700.0, 4700.0, 1655.5, 1243.5, {-0.03, 0.05, 1e-4, -2e-4, 0.0}, 3312, 2488};
  CameraIntrinsics right{4696.0, 4698.0, 1650.0, 1240.0, {-0.025, 0.04, -1e-4, 1e-4, 0.0}, 3312, 2488};
  const Isometry3 right_from_left = LookAt(Vec3(200.0, 0.0, 0.0), aim);
  if (name == "small") {
    // Crop 640×512 windows (camera ROIs) around where the ball centre images.
    for (CameraIntrinsics* cam : {&left, &right}) {
      const Isometry3 view = cam == &left ? Isometry3::Identity() : right_from_left;
      const Vec2 px = ProjectPoint(*cam, view * ball);
      if (!((view * ball).z() > 0.0) || px.x() < 0 || px.y() < 0 || px.x() > cam->width - 1 || px.y() > cam->height - 1)
        throw InputError({"", 0, "--ball"}, "the ball centre is outside the thesis cameras' field");
      const double u0 = std::round(px.x() - 319.5), v0 = std::round(px.y() - 255.5);
      cam->cx -= u0;
      cam->cy -= v0;
      cam->width = 640;
      cam->height = 512;
    }
  }
  c.cameras.left = left;
  c.cameras.right = right;
  c.cameras.right_from_left = right_from_left;
  // Projector between the cameras, slightly above, aimed at the ball: 912×1140, square pixels,
  // LightCrafter 4500: 912 columns × 1140 rows on a 16:10 image, so rows are at half the column
  // pitch (fy = 2·fx); fx = 1280 px lights ≈ 500 × 312 mm at 700 mm.
  c.projector.intrinsics = {1280.0, 2560.0, 455.5, 569.5, {}, 912, 1140};
  c.projector.view_from_left = LookAt(Vec3(100.0, -40.0, 0.0), aim);
  c.scene.spheres.push_back({"ball", ball, 38.1 / 2.0, 0.8});
  c.scene.planes.push_back({"backdrop", Vec3(0.0, 0.0, 850.0), Vec3(0.0, 0.0, -1.0), 0.5});
  c.sequence = {PhaseShiftBlock(12, 64.0), GrayCodeBlock(7, true)};
  return c;
}

FringeSimulationConfig MakeFringeConfigForCalibration(const StereoCalibration& cameras) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.preset = "calibration";
  c.cameras = cameras;
  // The ball where the optical axes come closest: on the left axis (0, 0, z) at the z that
  // minimises the distance to the right axis x = C + s·a.
  const Isometry3 left_from_right = cameras.right_from_left.inverse();
  const Vec3 centre = left_from_right.translation();
  const Vec3 axis = left_from_right.linear().col(2);
  const Vec3 e = Vec3::UnitZ();
  const double b = e.dot(axis), d = e.dot(centre), f = axis.dot(centre);
  double z = (d - b * f) / std::max(1.0 - b * b, 1e-12);
  if (!(z > 100.0 && z < 5000.0)) z = 700.0;  // parallel or diverging axes
  const Vec3 ball(0.0, 0.0, z);
  c.scene.spheres[0].centre_in_left = ball;
  c.scene.planes[0].point_in_left = Vec3(0.0, 0.0, z + 150.0);
  // Projector between the cameras, slightly above, aimed at the ball; the preset's throw scaled to
  // the distance.
  c.projector.view_from_left = LookAt(0.5 * centre + Vec3(0.0, -40.0, 0.0), ball);
  c.projector.intrinsics.fx *= z / 700.0;
  c.projector.intrinsics.fy *= z / 700.0;
  return c;
}

EffectRealisation RealiseEffects(const FringeSimulationConfig& config, const std::vector<PatternFrame>& frames) {
  EffectRealisation r;
  std::seed_seq seq{static_cast<std::uint32_t>(config.seed), static_cast<std::uint32_t>(config.seed >> 32), 0xEFFEC7u};
  std::mt19937_64 rng(seq);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double sigma = DegToRad(config.effects.phase_shift_error);
  const std::size_t n = frames.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double z = normal(rng);  // drawn for every frame so realisations do not depend on the sequence mix
    r.shift_errors_rad.push_back(frames[i].type == BlockType::kPhaseShift ? sigma * z : 0.0);
    r.gains.push_back(1.0 + config.effects.intensity_drift * (n > 1 ? static_cast<double>(i) / (n - 1) : 0.0));
  }
  return r;
}

PinholeView RenderedCameraView(const FringeSimulationConfig& config, int camera) {
  PinholeView view;
  view.intrinsics = camera == 0 ? config.cameras.left : config.cameras.right;
  view.intrinsics.distortion.k1 += config.effects.lens_distortion_unmodelled;
  view.view_from_left = camera == 0 ? Isometry3::Identity() : config.cameras.right_from_left;
  return view;
}

StereoCalibration WrittenCalibration(const FringeSimulationConfig& config) { return config.cameras; }

camera::SamplingKernel RenderedKernel(const FringeSimulationConfig& config, int camera) {
  const CameraIntrinsics& c = camera == 0 ? config.cameras.left : config.cameras.right;
  if (c.sampling_kernel) return *c.sampling_kernel;
  return config.supersampling == 1 ? camera::SamplingKernel{0.0, 0.0} : camera::SamplingKernel{};
}

FringeSimulationConfig StateRenderedKernel(FringeSimulationConfig config) {
  const camera::SamplingKernel left = RenderedKernel(config, 0), right = RenderedKernel(config, 1);
  config.cameras.left.sampling_kernel = left;
  config.cameras.right.sampling_kernel = right;
  return config;
}

SimulatedCamera SimulateCamera(const FringeSimulationConfig& config, int camera, const ProgressCallback& progress) {
  ThrowIfInvalid(config.Validate(), "FringeSimulationConfig");
  std::vector<PatternFrame> frames = ExpandSequence(config.sequence);
  const EffectRealisation fx = RealiseEffects(config, frames);
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].shift_error_rad = fx.shift_errors_rad[i];
  RenderOptions ro;
  ro.supersampling = config.supersampling;
  ro.kernel = RenderedKernel(config, camera);
  ro.ambient = config.effects.ambient_light;
  ro.projector_gamma = config.effects.projector_nonlinearity;
  ro.projector_blur_px = config.effects.defocus;
  ro.direction = config.direction;
  ro.progress = progress;
  SimulatedCamera out;
  out.truth = RenderView(config.scene, RenderedCameraView(config, camera), config.projector, frames, ro);
  if (out.truth.cancelled) return out;
  out.images = SenseRadiance(config, out.truth.radiance, fx.gains, camera);
  return out;
}

std::vector<cv::Mat> SenseRadiance(const FringeSimulationConfig& config, const std::vector<cv::Mat>& radiance,
                                   const std::vector<double>& gains, int camera) {
  SensorOptions sensor = config.sensor;
  sensor.exposure *= config.effects.saturation;
  sensor.blur_sigma_px = config.effects.camera_defocus;
  sensor.soft_knee_fraction = config.effects.soft_knee_response;
  std::vector<cv::Mat> images;
  for (std::size_t i = 0; i < radiance.size(); ++i)
    images.push_back(
        ApplySensor(radiance[i], gains[i], sensor, config.seed, static_cast<std::uint64_t>(camera) * 1000 + i));
  return images;
}

SimulatedCamera ResenseCamera(const FringeSimulationConfig& config, const SimulatedCamera& rendered, int camera) {
  ThrowIfInvalid(config.Validate(), "FringeSimulationConfig");
  const std::vector<PatternFrame> frames = ExpandSequence(config.sequence);
  SimulatedCamera out;
  out.truth = rendered.truth;
  out.images = SenseRadiance(config, rendered.truth.radiance, RealiseEffects(config, frames).gains, camera);
  return out;
}

std::string FringeSimulationSummary::BriefReport() const {
  std::ostringstream s;
  if (cancelled) return "fringe simulation cancelled; nothing written";
  s << "simulated 2 x " << frames << " fringe images " << width << "x" << height << " in " << out_dir << " ("
    << static_cast<int>(std::round(seconds * 10)) / 10.0 << " s)";
  return s.str();
}

namespace {

// truth/truth.json: the scene, the cameras' truth files, the projector and every effect's realisation.
// truth.json's "render": the ray count and projector settings, and each camera's sampling kernel
// when the configuration states it.
json RenderJson(const FringeSimulationConfig& config) {
  json render = {{"supersampling", config.supersampling},
                 {"ambient", config.effects.ambient_light},
                 {"projector_gamma", config.effects.projector_nonlinearity},
                 {"projector_blur_px", config.effects.defocus}};
  const char* names[2] = {"left", "right"};
  for (int i = 0; i < 2; ++i) {
    const CameraIntrinsics& c = i == 0 ? config.cameras.left : config.cameras.right;
    if (c.sampling_kernel)
      render["sampling_kernel"][names[i]] = {{"fill_factor", c.sampling_kernel->fill_factor},
                                             {"psf_sigma_px", c.sampling_kernel->psf_sigma_px}};
  }
  return render;
}

json TruthJson(const FringeSimulationConfig& config, const EffectRealisation& fx, const json& effects,
               const json& truth_cameras) {
  json spheres = json::array();
  for (const Sphere& s : config.scene.spheres)
    spheres.push_back({{"name", s.name},
                       {"centre_in_left_mm", Vec3Json(s.centre_in_left)},
                       {"radius_mm", s.radius},
                       {"albedo", s.albedo}});
  json planes = json::array();
  for (const Plane& p : config.scene.planes)
    planes.push_back({{"name", p.name},
                      {"point_in_left_mm", Vec3Json(p.point_in_left)},
                      {"normal_in_left", Vec3Json(p.normal_in_left.normalized())},
                      {"albedo", p.albedo}});
  json shift_deg = json::array();
  for (double e : fx.shift_errors_rad) shift_deg.push_back(RadToDeg(e));
  return {
      {"frame", "left camera, mm"},
      {"seed", config.seed},
      {"effects", effects},
      {"spheres", spheres},
      {"planes", planes},
      {"object_ids", "spheres in order, then planes; -1 = no surface"},
      {"cameras", truth_cameras},
      {"projector",
       {{"intrinsics", IntrinsicsTruthJson(config.projector.intrinsics)},
        {"projector_from_left", PoseToJson(config.projector.view_from_left)}}},
      {"frames", {{"phase_shift_error_deg", shift_deg}, {"gain", fx.gains}}},
      {"render", RenderJson(config)},
      {"sensor",
       {{"bits", config.sensor.bits},
        {"exposure", config.sensor.exposure * config.effects.saturation},
        {"full_well_electrons", config.sensor.full_well_electrons},
        {"read_noise_electrons", config.sensor.read_noise_electrons},
        {"blur_sigma_px", config.effects.camera_defocus},
        {"soft_knee_fraction", config.effects.soft_knee_response},
        {"noise", config.sensor.noise}}},
      {"truth_images",
       "float32 TIFF per camera: projector_x/projector_y = projector pixel of the pixel-centre ray's first hit "
       "(NaN where the projector does not light it), depth = z in that camera's frame (mm, NaN: no surface), "
       "lit_fraction = share of the pixel's rays lit on the same object, object_id"}};
}

// The left camera against the projector (projector_calibration.yml, the projector as camera 2,
// projector_from_left as R, T) and monocular.json: the set's manifest with the left camera only.
void WriteMonocular(const FringeSimulationConfig& config, const fs::path& tmp, const json& manifest) {
  StereoCalibration projector_pair;
  projector_pair.left = WrittenCalibration(config).left;
  projector_pair.right = config.projector.intrinsics;
  projector_pair.right_from_left = config.projector.view_from_left;
  WriteStereoCalibration((tmp / "projector_calibration.yml").string(), projector_pair);
  json monocular = manifest;
  monocular.erase("calibration");
  monocular["projector_calibration"] = "projector_calibration.yml";
  monocular["cameras"] = {{"left", manifest.at("cameras").at("left")}};
  WriteFileAtomically((tmp / "monocular.json").string(), monocular.dump(2) + "\n");
}

}  // namespace

FringeSimulationSummary SimulateFringeSet(const FringeSimulationConfig& config, const std::string& out_dir,
                                          bool overwrite, const ProgressCallback& progress,
                                          const Provenance* provenance) {
  const auto start = std::chrono::steady_clock::now();
  ThrowIfInvalid(config.Validate(), "FringeSimulationConfig");
  // Written into a sibling temporary folder, moved into place when complete (core/outputs.h).
  StagedFolder staged(out_dir, overwrite, "--out");
  const fs::path tmp = staged.path();
  std::error_code ec;
  if (!fs::create_directories(tmp / "left", ec) || !fs::create_directories(tmp / "right", ec) ||
      !fs::create_directories(tmp / "truth", ec))
    throw InputError({tmp.string(), 0, "--out"}, "cannot create folder: " + ec.message());

  FringeSimulationSummary summary;
  summary.out_dir = out_dir;
  try {
    const std::vector<PatternFrame> frames = ExpandSequence(config.sequence);
    const EffectRealisation fx = RealiseEffects(config, frames);
    const char* names[2] = {"left", "right"};
    json manifest_cameras = json::object();
    json truth_cameras = json::array();
    for (int cam = 0; cam < 2; ++cam) {
      ProgressCallback cam_progress;
      if (progress)
        cam_progress = [&](const Progress& p) {
          return progress({std::string("render ") + names[cam], p.done, p.total});
        };
      SimulatedCamera sim = SimulateCamera(config, cam, cam_progress);
      if (sim.truth.cancelled) {
        summary.cancelled = true;
        return summary;
      }
      json images = json::array();
      for (std::size_t i = 0; i < sim.images.size(); ++i) {
        const std::string rel = std::string(names[cam]) + "/" + FrameName(static_cast<int>(i), config.frame_format);
        if (config.frame_format == "bmp") {
          WriteImage((tmp / rel).string(), sim.images[i]);  // 8-bit (Validate)
        } else {
          WritePng((tmp / rel).string(), sim.images[i], config.sensor.bits);
        }
        images.push_back(rel);
      }
      manifest_cameras[names[cam]] = images;
      const std::string prefix = std::string("truth/") + names[cam] + "_";
      json files;
      for (const auto& [key, mat] :
           std::vector<std::pair<std::string, const cv::Mat*>>{{"projector_x", &sim.truth.projector_x},
                                                               {"projector_y", &sim.truth.projector_y},
                                                               {"depth", &sim.truth.depth},
                                                               {"lit_fraction", &sim.truth.lit_fraction},
                                                               {"object_id", &sim.truth.object_id}}) {
        WriteFloatTiff((tmp / (prefix + key + ".tif")).string(), *mat);
        files[key] = prefix + key + ".tif";
      }
      const PinholeView view = RenderedCameraView(config, cam);
      truth_cameras.push_back({{"name", names[cam]},
                               {"rendered_intrinsics", IntrinsicsTruthJson(view.intrinsics)},
                               {"camera_from_left", PoseToJson(view.view_from_left)},
                               {"files", files}});
      summary.width = sim.images.front().cols;
      summary.height = sim.images.front().rows;
      summary.frames = static_cast<int>(sim.images.size());
    }

    WriteStereoCalibration((tmp / "calibration.yml").string(), WrittenCalibration(config));

    json effects;
    for (const auto& [k, v] : config.effects.ByName()) effects[k] = v;
    json manifest = {
        {"format", "ramtk-fringe-set"},
        {"version", 1},
        {"projector", {{"width", config.projector.intrinsics.width}, {"height", config.projector.intrinsics.height}}},
        {"direction", FringeDirectionName(config.direction)},
        {"sequence", SequenceJson(config.sequence)},
        {"pattern_convention",
         "phase shift k of N: 0.5+0.5*cos(2*pi*cycles*c/L + phase_at_origin + 2*pi*k/N); gray code image i: bit "
         "(bits-1-i) of G(floor(c*2^bits/L)), G(n)=n^(n>>1), white=1; c = projector x (vertical fringes) in "
         "pixels, centres at integers"},
        {"cameras", manifest_cameras},
        {"bit_depth", config.sensor.bits},
        {"calibration", "calibration.yml"},
        {"simulation",
         {{"generator", "ramtk simulate fringe"},
          {"preset", config.preset},
          {"seed", config.seed},
          {"effects", effects},
          {"truth", "truth/truth.json"}}}};
    WriteFileAtomically((tmp / "manifest.json").string(), manifest.dump(2) + "\n");
    if (config.write_monocular) WriteMonocular(config, tmp, manifest);

    const json truth = TruthJson(config, fx, effects, truth_cameras);
    WriteFileAtomically((tmp / "truth" / "truth.json").string(), truth.dump(2) + "\n");
    if (provenance) WriteFolderProvenance(tmp.string(), *provenance);

    staged.Commit();
  } catch (const fs::filesystem_error& e) {
    throw InputError({out_dir, 0, "--out"}, std::string("cannot write the output: ") + e.what());
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

json IntrinsicsTruthJson(const CameraIntrinsics& c) {
  const Distortion& d = c.distortion;
  json j = {{"fx", c.fx},
            {"fy", c.fy},
            {"cx", c.cx},
            {"cy", c.cy},
            {"width", c.width},
            {"height", c.height},
            {"distortion_k1_k2_p1_p2_k3", {d.k1, d.k2, d.p1, d.p2, d.k3}}};
  if (d.model != camera::LensModel::kPinhole5) {
    j["lens_model"] = camera::LensModelName(d.model);
    j["distortion_opencv"] = camera::DistortionVector(d);
  }
  return j;
}

}  // namespace ramtk::vision
