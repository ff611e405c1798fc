#pragma once
// The fringe-image simulator behind `ramtk simulate fringe`: a stereo fringe-projection sensor
// (two cameras, one projector) looking at a ball and a backdrop, every fringe effect of the
// DESIGN.md catalogue switchable with a magnitude, and its outputs: the image set with its
// manifest, the stereo calibration file and the ground truth (docs/formats.md).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/sim/fringe_renderer.h"
#include "ramtk/vision/sim/scene.h"

namespace ramtk {
struct Provenance;  // ramtk/core/provenance.h
}  // namespace ramtk

namespace ramtk::vision {

// Magnitudes of the fringe-image effects (DESIGN.md effect catalogue). Each field's default is
// "off".
struct FringeEffects {
  // One double per row of fringe_effects.def (its name, at its "off" magnitude; the row's help
  // says what it does).
#define RAMTK_FRINGE_EFFECT(name, off, unit, help) double name = off;
#include "ramtk/vision/sim/fringe_effects.def"

  // Sets the effect `name` (catalogue identifier) to `magnitude`. Throws InputError (field `where`)
  // for an unknown name or an out-of-range magnitude.
  void Set(const std::string& name, double magnitude, const std::string& where = "--effect");
  // All effects by catalogue name, with their current magnitudes.
  std::map<std::string, double> ByName() const;
  // The table's names in its order (fringe_effects.def).
  static std::vector<std::string> Names();
  // "name (unit), ..." for every row: `--effect` help and the unknown-name error.
  static std::string Help();
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// Everything that defines a simulated stereo fringe set.
struct FringeSimulationConfig {
  std::string preset;                                          // preset it was made from ("thesis", "small", or "")
  StereoCalibration cameras;                                   // true cameras: intrinsics, distortion, right_from_left
  PinholeView projector;                                       // projector intrinsics and projector_from_left
  Scene scene;                                                 // spheres and planes, left-camera frame, mm
  std::vector<SequenceBlock> sequence;                     // projected pattern sequence
  FringeDirection direction = FringeDirection::kVertical;  // fringe direction
  // n×n rays per camera pixel, through each camera's sampling kernel (cameras.*.sampling_kernel;
  // not stated: the box pixel, fill factor 1, and with n = 1 a point sample; RenderedKernel).
  int supersampling = 4;
  SensorOptions sensor;    // bit depth, exposure, noise, (blur is set by `camera_defocus`)
  FringeEffects effects;   // effect magnitudes
  std::uint64_t seed = 1;  // seeds every random draw (effects and noise)
  // How SimulateFringeSet writes the frames: "png" (any bit depth), or "bmp" (uncompressed, 8-bit
  // sensors only; what many cameras write, and read by rows under `ramtk scan --roi`).
  std::string frame_format = "png";
  // Also write the left camera as a camera–projector set: projector_calibration.yml (the left
  // camera and the projector in the stereo keys, the projector as camera 2; docs/formats.md
  // "Projector calibration") and monocular.json (the left camera's frames naming it).
  bool write_monocular = false;

  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// Presets: "thesis" — 3312×2488 cameras (f = 4700 px), a 912×1140 projector, ~700 mm working
// distance, 200 mm baseline, the 38.1 mm ball at 700 mm in front of the left camera and a backdrop
// plane at 850 mm; the SLMaster sequence (12-step phase shift, 64 cycles, 7-bit complementary Gray
// code). "small" — the same rig with 640×512 cameras cropped around the ball (tests use it).
// Throws InputError (field "--preset") for another name.
FringeSimulationConfig MakeFringePreset(const std::string& name);
// The same rig (still aimed at (0, 0, 700)) with the ball at `ball_in_left`; the "small" preset's
// 640×512 windows are cropped around where it images (InputError, field "--ball", if outside).
FringeSimulationConfig MakeFringePreset(const std::string& name, const Vec3& ball_in_left);

// The same configuration with both cameras' windows resampled by `scale` (0.25: a 640×512
// window becomes 160×128 with 4× larger pixels over the same field): focal lengths and sizes
// scale, and the principal point keeps pixel centres at integers, c' = (c + 0.5)·scale − 0.5.
// The campaign twin renders its balls this way.
FringeSimulationConfig ScaleCameraWindows(FringeSimulationConfig config, double scale);

// The "small" preset's scene and projector around the cameras of a stereo calibration (e.g.
// SLMaster's caliInfo.yml): the ball where the two optical axes come closest (on the left axis),
// the backdrop 150 mm behind it, the projector between the cameras aimed at the ball.
FringeSimulationConfig MakeFringeConfigForCalibration(const StereoCalibration& cameras);

// Random realisations of the effects for one seed.
struct EffectRealisation {
  std::vector<double> shift_errors_rad;  // ε_k per frame (0 for Gray-code frames)
  std::vector<double> gains;             // camera gain per frame (intensity drift)
};
EffectRealisation RealiseEffects(const FringeSimulationConfig& config, const std::vector<PatternFrame>& frames);

// The views the renderer uses: cameras with the true (rendered) distortion, including the
// unmodelled part, and the calibration written for users (without it).
PinholeView RenderedCameraView(const FringeSimulationConfig& config, int camera);  // 0 left, 1 right
StereoCalibration WrittenCalibration(const FringeSimulationConfig& config);
// The sampling kernel camera `camera` (0 left, 1 right) is rendered with: its stated kernel, else
// the box pixel (fill factor 1, no PSF) for supersampling ≥ 2 and a point sample (fill factor 0)
// for supersampling 1.
camera::SamplingKernel RenderedKernel(const FringeSimulationConfig& config, int camera);
// The same configuration with both cameras' kernels stated as RenderedKernel: the render is the
// same and WrittenCalibration states the kernel it used (`ramtk simulate fringe` does this).
FringeSimulationConfig StateRenderedKernel(FringeSimulationConfig config);

// One camera's simulated images and ground truth, in memory.
struct SimulatedCamera {
  std::vector<cv::Mat> images;  // CV_8U or CV_16U per frame
  RenderedView truth;           // radiance (kept), projector coordinates, depth, object ids
};
SimulatedCamera SimulateCamera(const FringeSimulationConfig& config, int camera, const ProgressCallback& progress = {});

// The sensor's images of one camera's radiance frames (per-frame gains from the intensity drift)
// under config's sensor and effects, noise drawn from config.seed: SimulateCamera's last step.
std::vector<cv::Mat> SenseRadiance(const FringeSimulationConfig& config, const std::vector<cv::Mat>& radiance,
                                   const std::vector<double>& gains, int camera);

// `rendered` (a SimulateCamera result of the same scene) sensed again under config, e.g. with
// another seed: fresh sensor noise on one render, as SimulateCamera would draw it.
SimulatedCamera ResenseCamera(const FringeSimulationConfig& config, const SimulatedCamera& rendered, int camera);

// What SimulateFringeSet wrote.
struct FringeSimulationSummary {
  std::string out_dir;  // the output folder
  int frames = 0;       // images per camera
  int width = 0, height = 0;
  double seconds = 0.0;    // wall time
  bool cancelled = false;  // the progress callback stopped it; nothing was written
  std::string BriefReport() const;
};

// Renders both cameras and writes into `out_dir` (created; it must not exist or be empty unless
// `overwrite`): manifest.json, calibration.yml (with write_monocular also monocular.json and
// projector_calibration.yml), left/NN.png, right/NN.png (10/12-bit images scaled
// to 16-bit full scale; NN.bmp with frame_format "bmp"), and truth/ (per camera
// float TIFFs projector_x, projector_y, depth, lit_fraction and object_id, plus truth.json).
// Everything is written into a temporary sibling folder renamed into place at the end, so a
// failure leaves no partial output. With `provenance`, the folder also gets provenance.json
// (core/provenance.h WriteFolderProvenance).
FringeSimulationSummary SimulateFringeSet(const FringeSimulationConfig& config, const std::string& out_dir,
                                          bool overwrite = false, const ProgressCallback& progress = {},
                                          const Provenance* provenance = nullptr);

}  // namespace ramtk::vision
