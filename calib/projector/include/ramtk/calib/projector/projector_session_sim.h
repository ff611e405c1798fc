#pragma once
// Rendered projector calibration sessions with truth (`ramtk simulate projector-session`): a
// chessboard in N poses in front of one camera and one projector, every pose lit by the fringe
// sequence in both directions, as the camera's sensor records it.
//
// Rendering: each camera pixel is the mean of s×s rays (stratified, jittered at a fixed hash of the
// sub-pixel cell, as BoardRenderer), each ray the exact undistorted direction of its sub-pixel
// (camera::PixelRay), met with the board plane. The board point X has the chessboard's albedo
// (black / white squares, a white margin of one square; nothing off the board), its projector
// pixel is ProjectPoint(projector, projector_from_camera·X) (the projector's distortion included),
// and its radiance for frame f is albedo·(ambient + P_f(c)·n·l), P_f the codec's ideal intensity
// (codec.h) at the projector coordinate c along the frame's direction, n·l the cosine towards
// the projector centre; outside the projector image only the ambient term remains. The sensor
// (vision::ApplySensor: shot and read noise, quantisation) turns the pixel means into images.
//
// The board is found in the decoded background of the vertical fringes (the phase-shift frames'
// mean A), a flat-lit image of the board: no extra white frame is needed.

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/calib/board.h"
#include "ramtk/camera/camera_model.h"
#include "ramtk/core/progress.h"
#include "ramtk/core/rotation.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/sim/fringe_renderer.h"

namespace ramtk::calib {

struct ProjectorSessionSimOptions {
  BoardSpec board;                                          // chessboard only (set by Defaults: chessboard:9x6:20)
  int poses = 12;                                           // board poses (>= 4)
  std::uint64_t seed = 1;                                   // seeds the poses and the sensor noise
  camera::CameraIntrinsics camera;                          // the camera, its image size and distortion
  camera::CameraIntrinsics projector;                       // the projector as an inverse camera, its resolution
  Isometry3 projector_from_camera = Isometry3::Identity();  // x_projector = R·x_camera + T (mm)
  std::vector<vision::SequenceBlock> sequence;              // projected in each direction
  int supersampling = 2;                                    // s: s×s rays per camera pixel (1..8)
  double ambient = 0.05;                                    // ambient irradiance, fraction of the projector's white
  double black_albedo = 0.25;                               // albedo of the dark squares
  double white_albedo = 0.85;                               // albedo of the light squares and the margin
  vision::SensorOptions sensor;                             // bit depth, exposure, noise
  double distance_mm[2] = {420.0, 580.0};                   // range of the board centre's distance from the camera
  double max_tilt_deg = 35.0;                               // largest tilt of the board from facing the camera
  double max_offset_mm = 40.0;                              // board centre off the aim point, each of x and y
  Vec3 aim_in_camera = Vec3(0.0, 0.0, 500.0);               // where the poses gather (camera frame, mm)
  double edge_margin_px = 12.0;                             // every corner at least this far inside both images

  // The default rig: an 800×600 camera (f 1100 px, k1 −0.12) and a 1024×768 projector (f 1450 px,
  // principal point low in its image, k1 0.06) 150 mm to its right, toed in towards (0, 0, 500);
  // 8-step phase shift (32 periods) and a 6-bit complementary Gray code in each direction; an 8-bit
  // sensor at exposure 0.9.
  static ProjectorSessionSimOptions Defaults();
  // Aims the poses at the point `distance_mm` along the ray of the camera's image centre, with the
  // distance range ±16 % of it and the offsets ±0.11 × the camera's field width there (the default
  // rig's proportions); for another camera or working distance.
  void AimAtImageCentre(double distance);
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// One rendered pose.
struct ProjectorSessionPoseRender {
  std::string name;                                     // "pose00", ...
  Isometry3 camera_from_board = Isometry3::Identity();  // truth (mm)
  std::vector<cv::Mat> vertical;                        // sensor images, vertical fringes, in sequence order
  std::vector<cv::Mat> horizontal;                      // the same for horizontal fringes
};

// The board poses (camera_from_board) drawn from the seed: centre within the distance range and
// offsets, tilt up to max_tilt_deg about a random axis in the board plane, a random roll; each with
// every corner inside both the camera and the projector image by edge_margin_px. InputError if the
// rig cannot fit that many.
std::vector<Isometry3> DrawProjectorSessionPoses(const ProjectorSessionSimOptions& options);

// Renders pose `index` (its noise streams derive from the seed and the index).
ProjectorSessionPoseRender RenderProjectorSessionPose(const ProjectorSessionSimOptions& options,
                                                      const Isometry3& camera_from_board, int index);

struct ProjectorSessionSimSummary {
  std::string out_dir;
  int poses = 0;
  int frames_per_direction = 0;
  int width = 0, height = 0;  // camera
  bool cancelled = false;     // the progress callback stopped it; nothing was written
  std::string BriefReport() const;
};

// Renders every pose and writes into `out_dir` (it must not exist or be empty unless `overwrite`):
// session.json, poseNN/vertical.json and horizontal.json (fringe-set manifests, camera "camera"),
// poseNN/vNN.png and hNN.png, truth/truth.json (camera and projector intrinsics, projector_from_camera,
// every pose's camera_from_board) and truth/projector_calibration.yml (the truth in the projector
// calibration file's layout). Written into a temporary sibling folder moved into place at the
// end: a failure or a cancellation leaves nothing.
ProjectorSessionSimSummary SimulateProjectorSession(const ProjectorSessionSimOptions& options,
                                                    const std::string& out_dir, bool overwrite = false,
                                                    const ProgressCallback& progress = {});

}  // namespace ramtk::calib
