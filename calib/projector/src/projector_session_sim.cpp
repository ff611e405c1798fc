#include "ramtk/calib/projector/projector_session_sim.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "ramtk/calib/projector/projector_session.h"
#include "ramtk/core/cell_jitter.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/image/image_file.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/sim/truth_json.h"

namespace ramtk::calib {

namespace fs = std::filesystem;
using camera::Vec2;
using nlohmann::json;

namespace {

// Albedo of board point (x, y) (mm): chessboard squares, a white margin of one square, 0 off it.
double BoardAlbedo(const ProjectorSessionSimOptions& o, double x, double y) {
  const double sq = o.board.square_mm;
  if (x < -2 * sq || y < -2 * sq || x > (o.board.cols + 1) * sq || y > (o.board.rows + 1) * sq) return 0.0;
  if (x < -sq || y < -sq || x >= o.board.cols * sq || y >= o.board.rows * sq) return o.white_albedo;
  const long i = static_cast<long>(std::floor(x / sq)), j = static_cast<long>(std::floor(y / sq));
  return ((i + j) & 1) == 0 ? o.black_albedo : o.white_albedo;
}

// The rotation that turns unit vector a into unit vector b (the shortest one).
Mat3 RotationBetween(const Vec3& a, const Vec3& b) {
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

// One frame of the sequence: its block and image index.
struct FrameRef {
  const vision::SequenceBlock* block;
  const vision::PatternCodec* codec;
  int image;
};

std::vector<FrameRef> Frames(const std::vector<vision::SequenceBlock>& sequence) {
  std::vector<FrameRef> frames;
  for (const vision::SequenceBlock& b : sequence) {
    const vision::PatternCodec& codec = vision::CodecOf(b);
    for (int i = 0; i < b.ImageCount(); ++i) frames.push_back({&b, &codec, i});
  }
  return frames;
}

}  // namespace

ProjectorSessionSimOptions ProjectorSessionSimOptions::Defaults() {
  ProjectorSessionSimOptions o;
  o.board.type = BoardType::kChessboard;
  o.board.cols = 9;
  o.board.rows = 6;
  o.board.square_mm = 20.0;
  o.camera.fx = 1100.0;
  o.camera.fy = 1101.5;
  o.camera.cx = 405.3;
  o.camera.cy = 296.8;
  o.camera.width = 800;
  o.camera.height = 600;
  o.camera.distortion.k1 = -0.12;
  o.camera.distortion.k2 = 0.09;
  o.camera.distortion.p1 = 4e-4;
  o.camera.distortion.p2 = -3e-4;
  o.projector.fx = 1450.0;
  o.projector.fy = 1452.0;
  o.projector.cx = 517.4;
  o.projector.cy = 690.0;
  o.projector.width = 1024;
  o.projector.height = 768;
  o.projector.distortion.k1 = 0.06;
  o.projector.distortion.k2 = -0.05;
  o.projector.distortion.p1 = -2e-4;
  o.projector.distortion.p2 = 3e-4;
  // The projector 150 mm to the camera's right (slightly up and back), its centre pixel's ray through
  // the aim point.
  const Vec3 centre(150.0, -20.0, 10.0);
  const Vec3 to_aim = (o.aim_in_camera - centre).normalized();
  const Vec3 centre_pixel_ray = Vec3((0.5 * (o.projector.width - 1) - o.projector.cx) / o.projector.fx,
                                     (0.5 * (o.projector.height - 1) - o.projector.cy) / o.projector.fy, 1.0)
                                    .normalized();
  const Mat3 rotation = RotationBetween(to_aim, centre_pixel_ray);
  o.projector_from_camera.linear() = rotation;
  o.projector_from_camera.translation() = -rotation * centre;
  o.sequence = {vision::PhaseShiftBlock(8, 32.0), vision::GrayCodeBlock(6, true)};
  o.sensor.bits = 8;
  o.sensor.exposure = 0.9;
  return o;
}

void ProjectorSessionSimOptions::AimAtImageCentre(double distance) {
  const Vec3 ray = camera::PixelRay(camera, Vec2(0.5 * (camera.width - 1), 0.5 * (camera.height - 1)));
  aim_in_camera = ray * (distance / ray.z());
  distance_mm[0] = 0.84 * distance;
  distance_mm[1] = 1.16 * distance;
  max_offset_mm = 0.11 * camera.width * distance / camera.fx;
}

std::string ProjectorSessionSimOptions::Validate() const {
  if (board.type != BoardType::kChessboard) return "board: the simulator renders chessboards only";
  const std::string bad_board = board.Validate();
  if (!bad_board.empty()) return "board: " + bad_board;
  if (poses < 4 || poses > 1000) return "poses: must be in 4..1000";
  if (camera.width <= 0 || camera.height <= 0) return "camera: image size must be positive";
  if (projector.width <= 0 || projector.height <= 0) return "projector: resolution must be positive";
  if (sequence.empty()) return "sequence: must not be empty";
  if (supersampling < 1 || supersampling > 8) return "supersampling: must be in 1..8";
  if (!(ambient >= 0.0 && ambient < 1.0)) return "ambient: must be in [0, 1)";
  if (!(black_albedo >= 0.0 && black_albedo < white_albedo && white_albedo <= 1.0))
    return "black_albedo/white_albedo: need 0 <= black < white <= 1";
  if (!(distance_mm[0] > 0.0 && distance_mm[0] <= distance_mm[1])) return "distance_mm: need 0 < near <= far";
  if (!(max_tilt_deg >= 0.0 && max_tilt_deg < 80.0)) return "max_tilt_deg: must be in [0, 80)";
  if (!(max_offset_mm >= 0.0)) return "max_offset_mm: must be >= 0";
  if (!(edge_margin_px >= 0.0)) return "edge_margin_px: must be >= 0";
  const std::string bad_sensor = sensor.Validate();
  if (!bad_sensor.empty()) return "sensor." + bad_sensor;
  return "";
}

std::vector<Isometry3> DrawProjectorSessionPoses(const ProjectorSessionSimOptions& o) {
  ThrowIfInvalid(o.Validate(), "ProjectorSessionSimOptions");
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<cv::Point3f> corners = BoardObjectPoints(o.board);
  const Vec3 board_centre(0.5 * (o.board.cols - 1) * o.board.square_mm, 0.5 * (o.board.rows - 1) * o.board.square_mm,
                          0.0);
  const Mat3 camera_from_projector = o.projector_from_camera.linear().transpose();
  const Vec3 projector_centre = -camera_from_projector * o.projector_from_camera.translation();
  auto inside = [&](const Vec2& p, int w, int h) {
    return p.x() >= o.edge_margin_px && p.y() >= o.edge_margin_px && p.x() <= w - 1 - o.edge_margin_px &&
           p.y() <= h - 1 - o.edge_margin_px;
  };
  std::vector<Isometry3> poses;
  for (int attempt = 0; static_cast<int>(poses.size()) < o.poses; ++attempt) {
    if (attempt > 200 * o.poses)
      throw InputError({"", 0, "poses"}, "only " + std::to_string(poses.size()) +
                                             " board poses fit both images; the rig cannot hold " +
                                             std::to_string(o.poses));
    // Tilt magnitudes spread over the range, each pose about its own axis in the board plane.
    const double tilt = (o.max_tilt_deg * kRadPerDeg) * (0.25 + 0.75 * unit(rng));
    const double axis_angle = 2.0 * kPi * unit(rng), roll = (20.0 * kRadPerDeg) * (2.0 * unit(rng) - 1.0);
    const Vec3 axis(std::cos(axis_angle), std::sin(axis_angle), 0.0);
    const Mat3 rotation =
        Eigen::AngleAxisd(tilt, axis).toRotationMatrix() * Eigen::AngleAxisd(roll, Vec3::UnitZ()).toRotationMatrix();
    Vec3 centre =
        o.aim_in_camera + Vec3(o.max_offset_mm * (2 * unit(rng) - 1), o.max_offset_mm * (2 * unit(rng) - 1), 0);
    centre.z() = o.distance_mm[0] + (o.distance_mm[1] - o.distance_mm[0]) * unit(rng);
    // Along the aim point's ray: the offsets stay around it at every distance.
    centre.head<2>() += o.aim_in_camera.head<2>() * (centre.z() / o.aim_in_camera.z() - 1.0);
    Isometry3 pose = Isometry3::Identity();
    pose.linear() = rotation;
    pose.translation() = centre - rotation * board_centre;
    // The board's lit side faces both the camera and the projector.
    const Vec3 normal = -rotation.col(2);
    if (normal.dot((-centre).normalized()) < 0.3 || normal.dot((projector_centre - centre).normalized()) < 0.3)
      continue;
    bool ok = true;
    for (const cv::Point3f& c : corners) {
      const Vec3 x = pose * Vec3(c.x, c.y, c.z);
      const Vec3 xp = o.projector_from_camera * x;
      if (x.z() <= 0 || xp.z() <= 0 || !inside(camera::ProjectPoint(o.camera, x), o.camera.width, o.camera.height) ||
          !inside(camera::ProjectPoint(o.projector, xp), o.projector.width, o.projector.height)) {
        ok = false;
        break;
      }
    }
    if (ok) poses.push_back(pose);
  }
  return poses;
}

ProjectorSessionPoseRender RenderProjectorSessionPose(const ProjectorSessionSimOptions& o,
                                                      const Isometry3& camera_from_board, int index) {
  ThrowIfInvalid(o.Validate(), "ProjectorSessionSimOptions");
  const std::vector<FrameRef> frames = Frames(o.sequence);
  const int w = o.camera.width, h = o.camera.height, s = o.supersampling, nf = static_cast<int>(frames.size());
  std::vector<cv::Mat> radiance(2 * nf);
  for (cv::Mat& m : radiance) m.create(h, w, CV_32F);
  const Mat3 r = camera_from_board.linear();
  const Vec3 t = camera_from_board.translation(), plane_normal = r.col(2);
  const Vec3 facing = -plane_normal;  // towards the camera
  const Vec3 projector_centre = -(o.projector_from_camera.linear().transpose() * o.projector_from_camera.translation());
  const int extent[2] = {o.projector.width, o.projector.height};

  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> sum(2 * nf);
    for (int y = rows.begin(); y != rows.end(); ++y) {
      Vec2 guess((0 - o.camera.cx) / o.camera.fx, (y - o.camera.cy) / o.camera.fy);
      for (int x = 0; x < w; ++x) {
        std::fill(sum.begin(), sum.end(), 0.0);
        for (int i = 0; i < s; ++i) {
          for (int j = 0; j < s; ++j) {
            const int cx = x * s + j, cy = y * s + i;
            const Vec2 pixel((cx + CellJitter(cx, cy, 0)) / s - 0.5, (cy + CellJitter(cx, cy, 1)) / s - 0.5);
            const Vec3 ray = camera::PixelRay(o.camera, pixel, guess);
            guess = ray.head<2>() / ray.z();
            const double denominator = plane_normal.dot(ray);
            if (std::abs(denominator) < 1e-12) continue;
            const double distance = plane_normal.dot(t) / denominator;
            if (distance <= 0) continue;
            const Vec3 point = distance * ray;
            const Vec3 on_board = r.transpose() * (point - t);
            const double albedo = BoardAlbedo(o, on_board.x(), on_board.y());
            if (albedo <= 0) continue;
            const Vec3 in_projector = o.projector_from_camera * point;
            const double cosine = facing.dot((projector_centre - point).normalized());
            Vec2 p(-1e9, -1e9);
            if (in_projector.z() > 0 && cosine > 0) p = camera::ProjectPoint(o.projector, in_projector);
            const bool lit =
                p.x() >= -0.5 && p.y() >= -0.5 && p.x() < o.projector.width - 0.5 && p.y() < o.projector.height - 0.5;
            for (int d = 0; d < 2; ++d) {
              const double coordinate = d == 0 ? p.x() : p.y();
              for (int f = 0; f < nf; ++f) {
                double value = o.ambient;
                if (lit)
                  value +=
                      cosine * frames[f].codec->intensity(*frames[f].block, frames[f].image, coordinate, extent[d]);
                sum[d * nf + f] += albedo * value;
              }
            }
          }
        }
        for (int k = 0; k < 2 * nf; ++k) radiance[k].at<float>(y, x) = static_cast<float>(sum[k] / (s * s));
      }
    }
  });
  ProjectorSessionPoseRender out;
  char name[32];
  std::snprintf(name, sizeof(name), "pose%02d", index);
  out.name = name;
  out.camera_from_board = camera_from_board;
  for (int k = 0; k < 2 * nf; ++k) {
    const cv::Mat image = vision::ApplySensor(radiance[k], 1.0, o.sensor, o.seed, 1000ULL * (index + 1) + k);
    (k < nf ? out.vertical : out.horizontal).push_back(image);
  }
  return out;
}

std::string ProjectorSessionSimSummary::BriefReport() const {
  return "simulated " + std::to_string(poses) + " board poses x 2 x " + std::to_string(frames_per_direction) +
         " fringe images " + std::to_string(width) + "x" + std::to_string(height) + " into " + out_dir;
}

ProjectorSessionSimSummary SimulateProjectorSession(const ProjectorSessionSimOptions& o, const std::string& out_dir,
                                                    bool overwrite, const ProgressCallback& progress) {
  ThrowIfInvalid(o.Validate(), "ProjectorSessionSimOptions");
  const std::vector<Isometry3> poses = DrawProjectorSessionPoses(o);
  StagedFolder staged(out_dir, overwrite, "--out");
  const fs::path tmp = staged.path();
  ProjectorSessionSimSummary summary;
  summary.out_dir = out_dir;
  ProjectorSession session;
  session.board = o.board.ToString();
  json truth_poses = json::array();
  for (int p = 0; p < static_cast<int>(poses.size()); ++p) {
    if (progress && !progress({"render", static_cast<std::size_t>(p), poses.size()})) {
      summary.cancelled = true;
      return summary;
    }
    const ProjectorSessionPoseRender render = RenderProjectorSessionPose(o, poses[p], p);
    fs::create_directories(tmp / render.name);
    for (int d = 0; d < 2; ++d) {
      const std::vector<cv::Mat>& images = d == 0 ? render.vertical : render.horizontal;
      vision::FringeManifest manifest;
      manifest.projector_width = o.projector.width;
      manifest.projector_height = o.projector.height;
      manifest.direction = d == 0 ? vision::FringeDirection::kVertical : vision::FringeDirection::kHorizontal;
      manifest.sequence = o.sequence;
      std::vector<std::string> files;
      for (std::size_t i = 0; i < images.size(); ++i) {
        char file[32];
        std::snprintf(file, sizeof(file), "%c%02zu.png", d == 0 ? 'v' : 'h', i);
        image::WriteImage((tmp / render.name / file).string(), images[i]);
        files.push_back(file);
      }
      manifest.cameras["camera"] = files;
      const std::string manifest_name = d == 0 ? "vertical.json" : "horizontal.json";
      vision::WriteFringeManifest((tmp / render.name / manifest_name).string(), manifest);
    }
    session.poses.push_back({render.name, render.name + "/vertical.json", render.name + "/horizontal.json"});
    truth_poses.push_back({{"name", render.name}, {"camera_from_board", PoseToJson(render.camera_from_board)}});
    summary.frames_per_direction = static_cast<int>(render.vertical.size());
  }
  WriteFileAtomically((tmp / "session.json").string(), ProjectorSessionJson(session));
  fs::create_directories(tmp / "truth");
  vision::ProjectorCalibration truth;
  truth.camera = o.camera;
  truth.projector = o.projector;
  truth.projector_from_camera = o.projector_from_camera;
  vision::WriteProjectorCalibration((tmp / "truth" / "projector_calibration.yml").string(), truth);
  const json truth_json = {{"generator", "ramtk simulate projector-session"},
                           {"board", o.board.ToString()},
                           {"seed", o.seed},
                           {"supersampling", o.supersampling},
                           {"sensor",
                            {{"bits", o.sensor.bits},
                             {"exposure", o.sensor.exposure},
                             {"full_well_electrons", o.sensor.full_well_electrons},
                             {"read_noise_electrons", o.sensor.read_noise_electrons}}},
                           {"camera", vision::IntrinsicsTruthJson(o.camera)},
                           {"projector", vision::IntrinsicsTruthJson(o.projector)},
                           {"projector_from_camera", PoseToJson(o.projector_from_camera)},
                           {"poses", truth_poses}};
  WriteFileAtomically((tmp / "truth" / "truth.json").string(), truth_json.dump(2) + "\n");
  staged.Commit();
  summary.poses = static_cast<int>(poses.size());
  summary.width = o.camera.width;
  summary.height = o.camera.height;
  return summary;
}

}  // namespace ramtk::calib
