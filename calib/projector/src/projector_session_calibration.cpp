#include "ramtk/calib/projector/projector_session_calibration.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::calib {

using nlohmann::json;

namespace {

// One pose's corners in both devices.
struct PoseCorners {
  ViewPoints camera, projector;
  ProjectorPoseReport report;
  cv::Size camera_size, projector_size;
};

std::string CameraOf(const vision::FringeManifest& m) {
  if (m.cameras.count("camera")) return "camera";
  if (m.cameras.size() == 1) return m.cameras.begin()->first;
  throw InputError({m.path, 0, "cameras"}, "a session pose names one camera (or one called \"camera\")");
}

vision::FringeManifest ReadPoseManifest(const std::string& path, vision::FringeDirection direction,
                                        const std::string& session_path, const std::string& field) {
  vision::FringeManifest m;
  try {
    m = vision::ReadFringeManifest(path);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({session_path, 0, field}, e.message());
  }
  if (m.direction != direction)
    throw InputError({path, 0, "direction"}, std::string("must be \"") + vision::FringeDirectionName(direction) +
                                                 "\" (the session names it as " + field + ")");
  return m;
}

// The decoded background (the phase-shift frames' mean) as an 8-bit image: the flat-lit board.
cv::Mat FlatImage(const vision::DecodedCamera& decoded) {
  cv::Mat background = decoded.background.clone();
  cv::patchNaNs(background, 0.0);
  double max_value = 0.0;
  cv::minMaxLoc(background, nullptr, &max_value);
  cv::Mat gray;
  background.convertTo(gray, CV_8U, max_value > 0 ? 255.0 / max_value : 1.0);
  return gray;
}

PoseCorners FindPoseCorners(const ProjectorSession& session, std::size_t index, const BoardSpec& board,
                            const ProjectorSessionOptions& options) {
  const ProjectorSessionPose& pose = session.poses[index];
  const std::string where = "poses[" + std::to_string(index) + "].";
  const vision::FringeManifest columns_manifest = ReadPoseManifest(
      session.Resolve(pose.vertical), vision::FringeDirection::kVertical, session.path, where + "vertical");
  const vision::FringeManifest rows_manifest = ReadPoseManifest(
      session.Resolve(pose.horizontal), vision::FringeDirection::kHorizontal, session.path, where + "horizontal");
  if (rows_manifest.projector_width != columns_manifest.projector_width ||
      rows_manifest.projector_height != columns_manifest.projector_height)
    throw InputError({rows_manifest.path, 0, "projector"},
                     "projector resolution differs from " + columns_manifest.path + "'s");
  vision::DecodeOptions decode = options.decode;
  decode.keep_diagnostic_maps = true;  // the background is the flat-lit image
  const vision::DecodedCamera columns = vision::DecodeCamera(columns_manifest, CameraOf(columns_manifest), decode);
  const vision::DecodedCamera rows = vision::DecodeCamera(rows_manifest, CameraOf(rows_manifest), decode);
  if (rows.coordinate.size() != columns.coordinate.size())
    throw InputError({rows_manifest.path, 0, "cameras"}, "image size differs from " + columns_manifest.path + "'s");
  PoseCorners out;
  out.camera_size = columns.coordinate.size();
  out.projector_size = cv::Size(columns_manifest.projector_width, columns_manifest.projector_height);
  out.report.name = pose.name;
  const BoardDetection detection = DetectBoard(FlatImage(columns), board, options.detect);
  if (!detection.found) {
    out.report.reason = detection.reason.empty() ? "board not found" : detection.reason;
    return out;
  }
  out.camera = {pose.name, detection.image_points, detection.object_points, detection.ids};
  out.projector.name = pose.name;
  out.report.camera_corners = static_cast<int>(detection.image_points.size());
  const std::vector<vision::ProjectorCorner> corners =
      vision::ProjectorCornersFromPhase(detection.image_points, columns, rows, options.corners);
  std::vector<double> sigmas;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (!corners[k].valid) continue;
    out.projector.image_points.emplace_back(static_cast<float>(corners[k].projector_px.x()),
                                            static_cast<float>(corners[k].projector_px.y()));
    out.projector.object_points.push_back(detection.object_points[k]);
    out.projector.ids.push_back(detection.ids[k]);
    sigmas.push_back(std::max(corners[k].sigma_px.x(), corners[k].sigma_px.y()));
  }
  out.report.projector_corners = static_cast<int>(sigmas.size());
  if (!sigmas.empty()) {
    std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
    out.report.median_corner_sigma_px = sigmas[sigmas.size() / 2];
  }
  if (out.report.projector_corners < options.min_projector_corner_fraction * out.report.camera_corners) {
    out.report.reason = std::to_string(out.report.projector_corners) + " of " +
                        std::to_string(out.report.camera_corners) + " corners have a projector pixel";
  }
  return out;
}

// Fills each pose's per-device RMS from the stereo fit and the overall RMS of each device.
void ReportPoses(const std::vector<PoseCorners>& corners, ProjectorSessionResult* result) {
  const StereoCalibrationResult& st = result->stereo;
  double sum_camera = 0.0, sum_projector = 0.0;
  long points = 0;
  for (std::size_t i = 0; i < st.pair_names.size(); ++i) {
    const std::string name = st.pair_names[i].substr(0, st.pair_names[i].find('|'));
    for (std::size_t p = 0; p < corners.size(); ++p) {
      if (corners[p].report.name != name) continue;
      ProjectorPoseReport& r = result->poses[p];
      r.used = true;
      r.camera_rms_px = st.rig.per_view_errors_px[2 * i];
      r.projector_rms_px = st.rig.per_view_errors_px[2 * i + 1];
      const long n = static_cast<long>(corners[p].projector.image_points.size());
      sum_camera += n * r.camera_rms_px * r.camera_rms_px;
      sum_projector += n * r.projector_rms_px * r.projector_rms_px;
      points += n;
    }
  }
  result->camera_rms_px = points > 0 ? std::sqrt(sum_camera / points) : 0.0;
  result->projector_rms_px = points > 0 ? std::sqrt(sum_projector / points) : 0.0;
  std::vector<RejectedView> rejected = st.left.rejected;
  rejected.insert(rejected.end(), st.right.rejected.begin(), st.right.rejected.end());
  rejected.insert(rejected.end(), st.rejected_pairs.begin(), st.rejected_pairs.end());
  for (ProjectorPoseReport& r : result->poses) {
    if (r.used || !r.reason.empty()) continue;
    for (const RejectedView& v : rejected) {
      if (v.name == r.name || v.name == r.name + "|" + r.name) r.reason = "rejected: " + v.reason;
    }
    if (r.reason.empty()) r.reason = "not in the stereo fit";
  }
}

}  // namespace

std::string ProjectorSessionOptions::Validate() const {
  std::string bad = calibration.Validate();
  if (!bad.empty()) return "calibration." + bad;
  bad = corners.Validate();
  if (!bad.empty()) return "corners." + bad;
  bad = decode.Validate();
  if (!bad.empty()) return "decode." + bad;
  bad = detect.Validate();
  if (!bad.empty()) return "detect." + bad;
  if (!(min_projector_corner_fraction >= 0.0 && min_projector_corner_fraction <= 1.0))
    return "min_projector_corner_fraction: must be in [0, 1]";
  return "";
}

std::string ProjectorSessionSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << "calib projector ok: " << used_poses << " of " << poses << " poses; reprojection RMS " << camera_rms_px
    << " camera px, " << projector_rms_px << " projector px";
  return s.str();
}

ProjectorSessionResult CalibrateProjectorSession(const ProjectorSession& session, const BoardSpec& board,
                                                 const ProjectorSessionOptions& options,
                                                 ProjectorSessionSummary* summary) {
  ThrowIfInvalid(options.Validate(), "ProjectorSessionOptions");
  const std::string bad_board = board.Validate();
  if (!bad_board.empty()) throw InputError({"", 0, "board"}, bad_board);
  ProjectorSessionResult result;
  std::vector<PoseCorners> corners;
  std::vector<ViewPoints> camera_views, projector_views;
  for (std::size_t i = 0; i < session.poses.size(); ++i) {
    corners.push_back(FindPoseCorners(session, i, board, options));
    const PoseCorners& p = corners.back();
    if (p.camera_size != corners.front().camera_size || p.projector_size != corners.front().projector_size)
      throw InputError({session.Resolve(session.poses[i].vertical), 0, "projector"},
                       "camera image size or projector resolution differs from the first pose's");
    result.poses.push_back(p.report);
    if (p.report.reason.empty()) {
      camera_views.push_back(p.camera);
      projector_views.push_back(p.projector);
    } else {
      RAMTK_LOG(kInfo) << "calib projector: " << p.report.name << " not used: " << p.report.reason;
    }
    if (options.progress && !options.progress({"pose", i + 1, session.poses.size()}))
      throw InputError({session.path, 0, "poses"}, "cancelled");
  }
  if (corners.empty()) throw InputError({session.path, 0, "poses"}, "the session has no poses");
  result.camera_width = corners.front().camera_size.width;
  result.camera_height = corners.front().camera_size.height;
  result.projector_width = corners.front().projector_size.width;
  result.projector_height = corners.front().projector_size.height;
  if (static_cast<int>(camera_views.size()) < options.calibration.min_views) {
    throw InputError({session.path, 0, "poses"}, std::to_string(camera_views.size()) + " usable poses; at least " +
                                                     std::to_string(options.calibration.min_views) + " are needed");
  }
  if (options.progress) options.progress({"calibrate", 0, 1});
  CameraCalibrationOptions co = options.calibration;
  co.per_camera_variance = true;
  try {
    result.stereo =
        CalibrateStereo(camera_views, projector_views, corners.front().camera_size, corners.front().projector_size, co);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({session.path, 0, e.where().field.empty() ? "poses" : e.where().field}, e.message());
  }
  result.calibration = vision::FromStereoPair(result.stereo.rig);
  ReportPoses(corners, &result);
  if (summary) {
    summary->poses = static_cast<int>(session.poses.size());
    summary->used_poses = static_cast<int>(result.stereo.pair_names.size());
    summary->camera_rms_px = result.camera_rms_px;
    summary->projector_rms_px = result.projector_rms_px;
  }
  return result;
}

std::string ProjectorSessionResultJson(const ProjectorSessionResult& r, const BoardSpec& board) {
  const camera::StereoCalibration& rig = r.stereo.rig;
  std::vector<double> values;
  for (const camera::CameraIntrinsics* k : {&rig.left, &rig.right}) {
    const camera::Distortion& d = k->distortion;
    for (double v : {k->fx, k->fy, k->cx, k->cy, d.k1, d.k2, d.p1, d.p2, d.k3}) values.push_back(v);
  }
  cv::Matx33d rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rotation(i, j) = rig.right_from_left.linear()(i, j);
  cv::Vec3d rvec;
  cv::Rodrigues(rotation, rvec);
  for (int i = 0; i < 3; ++i) values.push_back(rvec[i]);
  for (int i = 0; i < 3; ++i) values.push_back(rig.right_from_left.translation()(i));
  std::istringstream names(camera::kCalibParameterStdOrder);
  json parameters = json::array();
  std::string name;
  for (std::size_t i = 0; names >> name && i < values.size(); ++i) {
    json p = {{"name", name}, {"value", values[i]}};
    p["std"] = i < rig.parameter_std.size() ? json(rig.parameter_std[i]) : json(nullptr);
    parameters.push_back(p);
  }
  json poses = json::array();
  auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  for (const ProjectorPoseReport& p : r.poses) {
    json j = {{"name", p.name},
              {"used", p.used},
              {"camera_corners", p.camera_corners},
              {"projector_corners", p.projector_corners},
              {"median_corner_sigma_px", number(p.median_corner_sigma_px)},
              {"camera_rms_px", number(p.camera_rms_px)},
              {"projector_rms_px", number(p.projector_rms_px)}};
    if (!p.reason.empty()) j["reason"] = p.reason;
    poses.push_back(j);
  }
  const json root = {
      {"format", "ramtk-projector-calibration-summary"},
      {"board", board.ToString()},
      {"camera_size", {r.camera_width, r.camera_height}},
      {"projector_size", {r.projector_width, r.projector_height}},
      {"rms_camera_px", r.camera_rms_px},
      {"rms_projector_px", r.projector_rms_px},
      {"rms_stereo_px", number(rig.rms_px)},
      {"camera_alone_rms_px", r.stereo.left.rms_px},
      {"projector_alone_rms_px", r.stereo.right.rms_px},
      {"parameter_units", "intrinsics px, rx ry rz rad (rotation vector of projector_from_camera), tx ty tz mm"},
      {"parameters", parameters},
      {"poses", poses}};
  return root.dump(2) + "\n";
}

}  // namespace ramtk::calib
