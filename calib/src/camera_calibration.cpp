#include "ramtk/calib/camera_calibration.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "lens_model_calibration.h"
#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/image/image_file.h"
#include "stereo_covariance.h"

namespace ramtk::calib {
namespace {

const cv::TermCriteria kCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

// Index of the view to reject, or -1: the worst view beyond both limits.
int WorstOutlier(const std::vector<double>& rms, const CameraCalibrationOptions& o, std::string* reason) {
  const double med = Median(rms);
  int worst = -1;
  for (int i = 0; i < static_cast<int>(rms.size()); ++i) {
    if (rms[i] > o.outlier_factor * med && rms[i] > o.outlier_min_px && (worst < 0 || rms[i] > rms[worst])) worst = i;
  }
  if (worst >= 0) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "RMS %.3f px > %.3g x median %.3f px", rms[worst], o.outlier_factor, med);
    *reason = buf;
  }
  return worst;
}

}  // namespace

std::string CameraCalibrationOptions::Validate() const {
  if (min_views < 3) return "min_views must be at least 3";
  if (!(outlier_factor > 1.0)) return "outlier_factor must exceed 1";
  if (!(outlier_min_px >= 0.0)) return "outlier_min_px must be >= 0";
  if (!(max_rejected_fraction >= 0.0 && max_rejected_fraction < 1.0)) return "max_rejected_fraction must be in [0, 1)";
  return "";
}

int CameraCalibrationOptions::OpenCvFlags() const {
  int f = 0;
  if (fix_k3) f |= cv::CALIB_FIX_K3;
  if (zero_tangential) f |= cv::CALIB_ZERO_TANGENT_DIST;
  if (fix_aspect_ratio) f |= cv::CALIB_FIX_ASPECT_RATIO;
  if (model == CalibrationModel::kRational || model == CalibrationModel::kThinPrism) f |= cv::CALIB_RATIONAL_MODEL;
  if (model == CalibrationModel::kThinPrism) f |= cv::CALIB_THIN_PRISM_MODEL;
  return f;
}

std::string CameraCalibrationSummary::BriefReport() const {
  char buf[400];
  std::snprintf(buf, sizeof(buf),
                "%s: %d rounds, %d views used, %zu rejected, RMS %.4f px (first round %.4f px), worst view %s %.4f px",
                message.c_str(), rounds, used_views, rejected.size(), final_rms_px, initial_rms_px, worst_view.c_str(),
                worst_view_rms_px);
  return buf;
}

CameraCalibrationResult CalibrateCamera(const std::vector<ViewPoints>& views_in, cv::Size image_size,
                                        const CameraCalibrationOptions& options, CameraCalibrationSummary* summary) {
  ThrowIfInvalid(options.Validate(), "CameraCalibrationOptions");
  CameraCalibrationSummary local;
  CameraCalibrationSummary& s = summary ? *summary : local;
  s = CameraCalibrationSummary();
  std::vector<ViewPoints> views;
  for (const ViewPoints& v : views_in) {
    if (v.image_points.size() >= 4 && v.image_points.size() == v.object_points.size()) views.push_back(v);
  }
  const int max_rejections = static_cast<int>(options.max_rejected_fraction * views.size());
  CameraCalibrationResult r;
  while (true) {
    if (static_cast<int>(views.size()) < options.min_views) {
      throw InputError({"", 0, "views"}, std::to_string(views.size()) + " usable views; at least " +
                                             std::to_string(options.min_views) + " are needed");
    }
    std::vector<std::vector<cv::Point3f>> obj;
    std::vector<std::vector<cv::Point2f>> img;
    for (const ViewPoints& v : views) {
      obj.push_back(v.object_points);
      img.push_back(v.image_points);
    }
    cv::Mat k, d, std_in, std_ex, per_view;
    std::vector<cv::Mat> rvecs, tvecs;
    r.rms_px = internal::CalibrateCameraModel(obj, img, image_size, options, kCriteria, &k, &d, &rvecs, &tvecs, &std_in,
                                              &std_ex, &per_view);
    ++s.rounds;
    if (s.rounds == 1) s.initial_rms_px = r.rms_px;
    std::vector<double> rms(per_view.begin<double>(), per_view.end<double>());
    std::string reason;
    const int worst = static_cast<int>(r.rejected.size()) < max_rejections ? WorstOutlier(rms, options, &reason) : -1;
    if (worst >= 0) {
      r.rejected.push_back({views[worst].name, reason});
      RAMTK_LOG(kInfo) << "camera calibration: rejected view " << views[worst].name << ": " << reason;
      views.erase(views.begin() + worst);
      continue;
    }
    r.intrinsics = camera::IntrinsicsFromOpenCv(cv::Matx33d(k), std::vector<double>(d.begin<double>(), d.end<double>()),
                                                image_size, LensModelOf(options.model));
    // σ of fx fy cx cy and of the coefficients the model writes (OpenCV returns 14 for the
    // rational model whatever it estimated).
    r.std_intrinsics.assign(std_in.begin<double>(),
                            std_in.begin<double>() + 4 + camera::DistortionVector(r.intrinsics.distortion).size());
    r.per_view_rms_px = rms;
    r.view_names.clear();
    r.rvecs.clear();
    r.tvecs.clear();
    r.std_extrinsics.clear();
    for (std::size_t i = 0; i < views.size(); ++i) {
      r.view_names.push_back(views[i].name);
      r.rvecs.emplace_back(rvecs[i]);
      r.tvecs.emplace_back(tvecs[i]);
      cv::Vec6d e;
      for (int j = 0; j < 6; ++j) e[j] = std_ex.at<double>(static_cast<int>(6 * i + j));
      r.std_extrinsics.push_back(e);
    }
    break;
  }
  s.termination = Termination::kSuccess;
  s.message = "converged";
  s.final_rms_px = r.rms_px;
  s.used_views = static_cast<int>(r.view_names.size());
  s.rejected = r.rejected;
  for (std::size_t i = 0; i < r.per_view_rms_px.size(); ++i) {
    if (r.per_view_rms_px[i] >= s.worst_view_rms_px) {
      s.worst_view_rms_px = r.per_view_rms_px[i];
      s.worst_view = r.view_names[i];
    }
  }
  return r;
}

StereoCalibrationResult CalibrateStereo(const std::vector<ViewPoints>& left, const std::vector<ViewPoints>& right,
                                        cv::Size image_size, const CameraCalibrationOptions& options,
                                        CameraCalibrationSummary* summary) {
  return CalibrateStereo(left, right, image_size, image_size, options, summary);
}

StereoCalibrationResult CalibrateStereo(const std::vector<ViewPoints>& left, const std::vector<ViewPoints>& right,
                                        cv::Size image_size, cv::Size right_size,
                                        const CameraCalibrationOptions& options, CameraCalibrationSummary* summary) {
  if (left.size() != right.size()) {
    throw InputError({"", 0, "views"}, "left and right view counts differ (" + std::to_string(left.size()) + " vs " +
                                           std::to_string(right.size()) + ")");
  }
  StereoCalibrationResult st;
  CameraCalibrationSummary sl, sr;
  st.left = CalibrateCamera(left, image_size, options, &sl);
  st.right = CalibrateCamera(right, right_size, options, &sr);
  // Pairs both cameras kept; common feature ids only.
  struct Pair {
    std::string name;
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> l, r;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < left.size(); ++i) {
    const bool in_l =
        std::find(st.left.view_names.begin(), st.left.view_names.end(), left[i].name) != st.left.view_names.end();
    const bool in_r =
        std::find(st.right.view_names.begin(), st.right.view_names.end(), right[i].name) != st.right.view_names.end();
    if (!in_l || !in_r) continue;
    std::map<int, std::size_t> right_index;
    for (std::size_t k = 0; k < right[i].ids.size(); ++k) right_index[right[i].ids[k]] = k;
    Pair p;
    p.name = left[i].name + "|" + right[i].name;
    for (std::size_t k = 0; k < left[i].ids.size(); ++k) {
      const auto it = right_index.find(left[i].ids[k]);
      if (it == right_index.end()) continue;
      p.obj.push_back(left[i].object_points[k]);
      p.l.push_back(left[i].image_points[k]);
      p.r.push_back(right[i].image_points[it->second]);
    }
    if (p.obj.size() >= 4) pairs.push_back(p);
  }
  const int max_rejections = static_cast<int>(options.max_rejected_fraction * pairs.size());
  int rounds = 0;
  while (true) {
    if (static_cast<int>(pairs.size()) < options.min_views) {
      throw InputError({"", 0, "views"}, std::to_string(pairs.size()) + " usable stereo pairs; at least " +
                                             std::to_string(options.min_views) + " are needed");
    }
    std::vector<std::vector<cv::Point3f>> obj;
    std::vector<std::vector<cv::Point2f>> il, ir;
    for (const Pair& p : pairs) {
      obj.push_back(p.obj);
      il.push_back(p.l);
      ir.push_back(p.r);
    }
    cv::Mat k1(camera::CameraMatrix(st.left.intrinsics)), k2(camera::CameraMatrix(st.right.intrinsics));
    cv::Mat d1 = internal::CalibrationDistortion(st.left.intrinsics, options.model);
    cv::Mat d2 = internal::CalibrationDistortion(st.right.intrinsics, options.model);
    cv::Mat rot, tr, per_view;
    // Joint refinement of both cameras and the rig from the single-camera starts.
    st.rig.rms_px = internal::StereoCalibrateModel(obj, il, ir, image_size, options, kCriteria, &k1, &d1, &k2, &d2,
                                                   &rot, &tr, &per_view);
    ++rounds;
    std::vector<double> worst_of_pair;
    for (int i = 0; i < per_view.rows; ++i) {
      worst_of_pair.push_back(std::max(per_view.at<double>(i, 0), per_view.at<double>(i, 1)));
    }
    std::string reason;
    const int worst = static_cast<int>(st.rejected_pairs.size()) < max_rejections
                          ? WorstOutlier(worst_of_pair, options, &reason)
                          : -1;
    if (worst >= 0) {
      st.rejected_pairs.push_back({pairs[worst].name, "stereo " + reason});
      pairs.erase(pairs.begin() + worst);
      continue;
    }
    st.rig.left =
        camera::IntrinsicsFromOpenCv(cv::Matx33d(k1), std::vector<double>(d1.begin<double>(), d1.end<double>()),
                                     image_size, LensModelOf(options.model));
    st.rig.right =
        camera::IntrinsicsFromOpenCv(cv::Matx33d(k2), std::vector<double>(d2.begin<double>(), d2.end<double>()),
                                     right_size, LensModelOf(options.model));
    const cv::Matx33d rotation(rot);
    const cv::Vec3d translation(tr);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) st.rig.right_from_left.linear()(i, j) = rotation(i, j);
      st.rig.right_from_left.translation()(i) = translation[i];
    }
    cv::Vec6d std_rt;
    std::vector<double> std_left, std_right;
    st.rig.parameter_std.clear();
    // The joint σ are the 5-coefficient model's (stereo_covariance.h); the other models have none.
    const bool pinhole5 = st.rig.left.distortion.model == camera::LensModel::kPinhole5 &&
                          st.rig.right.distortion.model == camera::LensModel::kPinhole5;
    if (!pinhole5) {
      RAMTK_LOG(kInfo) << "stereo calibration: no standard deviations for the "
                       << camera::LensModelName(LensModelOf(options.model)) << " lens model";
    } else if (internal::StereoExtrinsicStd(
                   obj, il, ir, camera::CameraMatrix(st.rig.left), camera::DistortionVector(st.rig.left.distortion),
                   camera::CameraMatrix(st.rig.right), camera::DistortionVector(st.rig.right.distortion), rotation,
                   translation, options.fix_k3, options.per_camera_variance, &std_rt, &std_left,
                   &std_right)) {
      st.rig.parameter_std = std_left;
      st.rig.parameter_std.insert(st.rig.parameter_std.end(), std_right.begin(), std_right.end());
      st.rig.parameter_std.insert(st.rig.parameter_std.end(), std_rt.val, std_rt.val + 6);
    } else {
      RAMTK_LOG(kWarning) << "stereo calibration: standard deviations could not be computed";
    }
    st.pair_names.clear();
    st.rig.per_view_errors_px.clear();
    for (int i = 0; i < per_view.rows; ++i) {
      st.pair_names.push_back(pairs[i].name);
      st.rig.per_view_errors_px.push_back(per_view.at<double>(i, 0));
      st.rig.per_view_errors_px.push_back(per_view.at<double>(i, 1));
    }
    break;
  }
  if (summary) {
    *summary = sl;
    summary->rounds = sl.rounds + sr.rounds + rounds;
    summary->final_rms_px = st.rig.rms_px;
    summary->used_views = static_cast<int>(st.pair_names.size());
    summary->rejected.insert(summary->rejected.end(), sr.rejected.begin(), sr.rejected.end());
    summary->rejected.insert(summary->rejected.end(), st.rejected_pairs.begin(), st.rejected_pairs.end());
    if (sr.worst_view_rms_px > summary->worst_view_rms_px) {
      summary->worst_view_rms_px = sr.worst_view_rms_px;
      summary->worst_view = sr.worst_view;
    }
  }
  return st;
}

std::vector<ViewPoints> DetectBoardInImages(const std::vector<std::string>& paths, const BoardSpec& board,
                                            cv::Size* image_size, std::vector<RejectedView>* rejected,
                                            const ProgressCallback& progress, std::vector<ViewPoints>* sector_based) {
  std::vector<ViewPoints> views(paths.size());
  if (sector_based) sector_based->assign(paths.size(), ViewPoints());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const cv::Mat img = image::LoadImageGrey8(paths[i]);
    if (image_size->area() == 0) *image_size = img.size();
    if (img.size() != *image_size) {
      throw InputError({paths[i], 0, ""}, "image size " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                              " differs from the first image's " + std::to_string(image_size->width) +
                                              "x" + std::to_string(image_size->height));
    }
    const BoardDetection d = DetectBoard(img, board);
    views[i].name = paths[i];
    if (d.found) {
      views[i].image_points = d.image_points;
      views[i].object_points = d.object_points;
      views[i].ids = d.ids;
      if (sector_based) {
        (*sector_based)[i].name = paths[i];
        if (!d.sector_points.empty()) {
          (*sector_based)[i].image_points = d.sector_points;
          (*sector_based)[i].object_points = d.object_points;
          (*sector_based)[i].ids = d.ids;
        }
      }
    } else if (rejected) {
      rejected->push_back({paths[i], d.reason});
    }
    if (progress && !progress({"detect", i + 1, paths.size()})) break;
  }
  return views;
}

cv::Mat DrawCoverage(const CameraCalibrationResult& cam, const std::vector<ViewPoints>& views, double residual_scale) {
  cv::Mat img(camera::ImageSize(cam.intrinsics), CV_8UC3, cv::Scalar(255, 255, 255));
  cv::rectangle(img, cv::Rect(0, 0, img.cols, img.rows), cv::Scalar(0, 0, 0), 1);
  for (const ViewPoints& v : views) {
    const auto it = std::find(cam.view_names.begin(), cam.view_names.end(), v.name);
    if (it == cam.view_names.end()) {
      for (const cv::Point2f& p : v.image_points) cv::circle(img, p, 2, cv::Scalar(180, 180, 180), cv::FILLED);
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(it - cam.view_names.begin());
    const std::vector<cv::Point2d> projected = camera::ProjectPointsOpenCv(
        {v.object_points.begin(), v.object_points.end()}, cam.rvecs[i], cam.tvecs[i], cam.intrinsics);
    const std::vector<cv::Point2f> proj(projected.begin(), projected.end());
    cv::Mat hue(1, 1, CV_8UC3,
                cv::Scalar(static_cast<int>(170 * i / std::max<std::size_t>(1, cam.view_names.size())), 200, 200));
    cv::cvtColor(hue, hue, cv::COLOR_HSV2BGR);
    const cv::Vec3b c = hue.at<cv::Vec3b>(0, 0);
    for (std::size_t k = 0; k < v.image_points.size(); ++k) {
      const cv::Point2f& p = v.image_points[k];
      cv::circle(img, p, 2, cv::Scalar(c[0], c[1], c[2]), cv::FILLED, cv::LINE_AA);
      const cv::Point2f tip = p + static_cast<float>(residual_scale) * (p - proj[k]);
      cv::line(img, p, tip, cv::Scalar(0, 0, 200), 1, cv::LINE_AA);
    }
  }
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%zu views, RMS %.3f px, residuals x%g", cam.view_names.size(), cam.rms_px,
                residual_scale);
  cv::putText(img, buf, cv::Point(10, 25), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return img;
}

}  // namespace ramtk::calib
