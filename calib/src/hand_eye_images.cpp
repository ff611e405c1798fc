#include "ramtk/calib/hand_eye_images.h"

#include "ramtk/core/error.h"

namespace ramtk::calib {

HandEyeViews HandEyeViewsFromDetections(const std::vector<ViewPoints>& views, const camera::CameraIntrinsics& camera,
                                        const std::vector<Isometry3>& base_from_flange,
                                        const BoardPoseOptions& options) {
  if (views.size() != base_from_flange.size())
    throw InputError({"", 0, "poses"}, std::to_string(views.size()) + " images, but " +
                                           std::to_string(base_from_flange.size()) + " flange poses");
  HandEyeViews out;
  const std::vector<BoardPoseEstimate> poses = EstimateBoardPoses(views, camera, options, &out.poses);
  std::size_t next = 0;
  for (const BoardPoseEstimate& p : poses) {
    while (next < views.size() && views[next].name != p.name) ++next;
    if (next == views.size()) throw InputError({"", 0, "views"}, "view names must be unique: " + p.name);
    FlangePoseObservation o;
    o.base_from_flange = base_from_flange[next];
    o.camera_from_board = p.camera_from_board;
    o.camera_from_board_covariance = p.covariance;
    out.observations.push_back(o);
    out.names.push_back(p.name);
    out.indices.push_back(static_cast<int>(next));
    ++next;
  }
  return out;
}

HandEyeViews HandEyeViewsFromImages(const std::vector<std::string>& image_paths, const BoardSpec& board,
                                    const camera::CameraIntrinsics& camera,
                                    const std::vector<Isometry3>& base_from_flange, const BoardPoseOptions& options,
                                    const ProgressCallback& progress) {
  if (image_paths.size() != base_from_flange.size())
    throw InputError({"", 0, "poses"}, std::to_string(image_paths.size()) + " images, but " +
                                           std::to_string(base_from_flange.size()) + " flange poses");
  cv::Size size(camera.width, camera.height);
  std::vector<RejectedView> not_found;
  const std::vector<ViewPoints> views = DetectBoardInImages(image_paths, board, &size, &not_found, progress);
  HandEyeViews out = HandEyeViewsFromDetections(views, camera, base_from_flange, options);
  for (RejectedView& s : out.poses.skipped)  // the detector's own reason
    for (const RejectedView& r : not_found)
      if (r.name == s.name) s.reason = r.reason;
  return out;
}

}  // namespace ramtk::calib
