// The calibration calls of each lens model (lens_model_calibration.h).
#include "lens_model_calibration.h"

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "ramtk/camera/opencv_camera.h"
#include "ramtk/core/error.h"

namespace ramtk::calib {

CalibrationModel ParseCalibrationModel(const std::string& text, const InputLocation& where) {
  if (text == "pinhole5") return CalibrationModel::kPinhole5;
  if (text == "rational") return CalibrationModel::kRational;
  if (text == "thin-prism") return CalibrationModel::kThinPrism;
  if (text == "fisheye") return CalibrationModel::kFisheye;
  throw InputError(where, "unknown lens model '" + text + "' (known: pinhole5, rational, thin-prism, fisheye)");
}

camera::LensModel LensModelOf(CalibrationModel model) {
  switch (model) {
    case CalibrationModel::kRational:
    case CalibrationModel::kThinPrism:
      return camera::LensModel::kRational;
    case CalibrationModel::kFisheye:
      return camera::LensModel::kFisheye;
    case CalibrationModel::kPinhole5:
    default:
      return camera::LensModel::kPinhole5;
  }
}

namespace internal {
namespace {

std::vector<cv::Point3d> Double(const std::vector<cv::Point3f>& p) { return {p.begin(), p.end()}; }

// Squared reprojection error of one view through the fisheye model, and (if `jac`) the Jacobian
// of its projections: 2n × 15, columns fx fy cx cy k1..k4 rvec tvec skew (cv::fisheye::projectPoints).
double FisheyeViewError(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image,
                        const cv::Mat& rvec, const cv::Mat& tvec, const cv::Mat& k, const cv::Mat& d, cv::Mat* residual,
                        cv::Mat* jac) {
  std::vector<cv::Point2d> proj;
  cv::fisheye::projectPoints(Double(object), proj, rvec, tvec, k, d, 0.0, jac ? *jac : cv::noArray());
  double sum = 0.0;
  if (residual) residual->create(static_cast<int>(2 * image.size()), 1, CV_64F);
  for (std::size_t i = 0; i < image.size(); ++i) {
    const double dx = image[i].x - proj[i].x, dy = image[i].y - proj[i].y;
    sum += dx * dx + dy * dy;
    if (residual)
      residual->at<double>(static_cast<int>(2 * i)) = dx, residual->at<double>(static_cast<int>(2 * i + 1)) = dy;
  }
  return sum;
}

// cv::fisheye::calibrate, then the σ of its 8 intrinsics and each view's pose from the Jacobian
// of every residual (Gauss-Newton's normal matrix scaled by the residual variance, as OpenCV's
// stdDeviationsIntrinsics).
double FisheyeCalibrate(const ObjectPoints& object, const ImagePoints& image, cv::Size image_size,
                        const cv::TermCriteria& criteria, cv::Mat* k, cv::Mat* d, std::vector<cv::Mat>* rvecs,
                        std::vector<cv::Mat>* tvecs, cv::Mat* std_in, cv::Mat* std_ex, cv::Mat* per_view) {
  cv::Mat kk, dd;
  std::vector<cv::Mat> rv, tv;
  cv::fisheye::calibrate(object, image, image_size, kk, dd, rv, tv,
                         cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW, criteria);
  const int views = static_cast<int>(object.size());
  const int params = 8 + 6 * views;
  cv::Mat normal = cv::Mat::zeros(params, params, CV_64F);
  per_view->create(views, 1, CV_64F);
  double total = 0.0;
  int points = 0;
  for (int v = 0; v < views; ++v) {
    cv::Mat residual, jac;
    const double sum = FisheyeViewError(object[v], image[v], rv[v], tv[v], kk, dd, &residual, &jac);
    const int n = static_cast<int>(object[v].size());
    per_view->at<double>(v) = std::sqrt(sum / n);
    total += sum;
    points += n;
    // This view's columns of the full Jacobian: the intrinsics, then its own pose.
    cv::Mat j = cv::Mat::zeros(2 * n, params, CV_64F);
    jac.colRange(0, 8).copyTo(j.colRange(0, 8));
    jac.colRange(8, 14).copyTo(j.colRange(8 + 6 * v, 14 + 6 * v));
    normal += j.t() * j;
  }
  const double variance = total / std::max(1, 2 * points - params);
  cv::Mat covariance;
  cv::invert(normal, covariance, cv::DECOMP_SVD);
  std_in->create(8, 1, CV_64F);
  std_ex->create(6 * views, 1, CV_64F);
  for (int i = 0; i < params; ++i) {
    const double s = std::sqrt(std::max(0.0, covariance.at<double>(i, i) * variance));
    (i < 8 ? std_in->at<double>(i) : std_ex->at<double>(i - 8)) = s;
  }
  *k = kk;
  *d = dd.reshape(1, static_cast<int>(dd.total()));
  *rvecs = rv;
  *tvecs = tv;
  return std::sqrt(total / std::max(1, points));
}

// cv::fisheye::stereoCalibrate with both cameras' intrinsics fixed; each pair's RMS from the left
// board pose (PnP on the undistorted corners) and that pose moved by R, T into the right camera.
double FisheyeStereo(const ObjectPoints& object, const ImagePoints& left, const ImagePoints& right, cv::Size image_size,
                     const cv::TermCriteria& criteria, const cv::Mat& k1, const cv::Mat& d1, const cv::Mat& k2,
                     const cv::Mat& d2, cv::Mat* rotation, cv::Mat* translation, cv::Mat* per_view) {
  cv::Mat r, t;
  cv::Mat k1c = k1.clone(), d1c = d1.clone(), k2c = k2.clone(), d2c = d2.clone();
  cv::fisheye::stereoCalibrate(object, left, right, k1c, d1c, k2c, d2c, image_size, r, t,
                               cv::fisheye::CALIB_FIX_INTRINSIC, criteria);
  const int views = static_cast<int>(object.size());
  per_view->create(views, 2, CV_64F);
  double total = 0.0;
  int points = 0;
  for (int v = 0; v < views; ++v) {
    std::vector<cv::Point2d> ideal;
    cv::fisheye::undistortPoints(std::vector<cv::Point2d>(left[v].begin(), left[v].end()), ideal, k1, d1);
    cv::Mat rvec, tvec;
    cv::solvePnP(Double(object[v]), ideal, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec);
    cv::Mat rl, rr_vec;
    cv::Rodrigues(rvec, rl);
    cv::Rodrigues(r * rl, rr_vec);
    const cv::Mat tr = r * tvec + t;
    const double sl = FisheyeViewError(object[v], left[v], rvec, tvec, k1, d1, nullptr, nullptr);
    const double sr = FisheyeViewError(object[v], right[v], rr_vec, tr, k2, d2, nullptr, nullptr);
    const int n = static_cast<int>(object[v].size());
    per_view->at<double>(v, 0) = std::sqrt(sl / n);
    per_view->at<double>(v, 1) = std::sqrt(sr / n);
    total += sl + sr;
    points += 2 * n;
  }
  *rotation = r;
  *translation = t;
  return std::sqrt(total / std::max(1, points));
}

}  // namespace

cv::Mat CalibrationDistortion(const camera::CameraIntrinsics& camera, CalibrationModel model) {
  std::vector<double> d = camera::DistortionVector(camera.distortion);
  const std::size_t n = model == CalibrationModel::kRational    ? 8
                        : model == CalibrationModel::kThinPrism ? 12
                        : model == CalibrationModel::kFisheye   ? 4
                                                                : 5;
  d.resize(n, 0.0);
  return cv::Mat(d, true);
}

double CalibrateCameraModel(const ObjectPoints& object, const ImagePoints& image, cv::Size image_size,
                            const CameraCalibrationOptions& options, const cv::TermCriteria& criteria, cv::Mat* k,
                            cv::Mat* d, std::vector<cv::Mat>* rvecs, std::vector<cv::Mat>* tvecs, cv::Mat* std_in,
                            cv::Mat* std_ex, cv::Mat* per_view) {
  if (options.model == CalibrationModel::kFisheye)
    return FisheyeCalibrate(object, image, image_size, criteria, k, d, rvecs, tvecs, std_in, std_ex, per_view);
  return cv::calibrateCamera(object, image, image_size, *k, *d, *rvecs, *tvecs, *std_in, *std_ex, *per_view,
                             options.OpenCvFlags(), criteria);
}

double StereoCalibrateModel(const ObjectPoints& object, const ImagePoints& left, const ImagePoints& right,
                            cv::Size image_size, const CameraCalibrationOptions& options,
                            const cv::TermCriteria& criteria, cv::Mat* k1, cv::Mat* d1, cv::Mat* k2, cv::Mat* d2,
                            cv::Mat* rotation, cv::Mat* translation, cv::Mat* per_view) {
  if (options.model == CalibrationModel::kFisheye)
    return FisheyeStereo(object, left, right, image_size, criteria, *k1, *d1, *k2, *d2, rotation, translation,
                         per_view);
  cv::Mat e, f;
  return cv::stereoCalibrate(object, left, right, *k1, *d1, *k2, *d2, image_size, *rotation, *translation, e, f,
                             *per_view, cv::CALIB_USE_INTRINSIC_GUESS | options.OpenCvFlags(), criteria);
}

}  // namespace internal
}  // namespace ramtk::calib
