// Fringe decoding, the scan pipeline, sphere fitting and the fringe simulator for the Python
// package (python/ramtk/_vision.py checks the arguments and builds the typed results). Frames
// come in as numpy arrays viewed without a copy; images and clouds go out the same way (the
// arrays keep the C++ buffers alive). Options arrive as a dict keyed by the command line's names.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "numpy_convert.h"
#include "progress_bridge.h"
#include "ramtk/camera/opencv_camera.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "ramtk/vision/sphere/sphere_fit.h"
#include "scan_options.h"

namespace ramtk::python {

py::list SpheresToPython(const vision::SphereFitSummary& s) {
  py::list out;
  for (const vision::SphereResult& r : s.spheres) {
    py::dict d;
    d["centre_mm"] = ToArray(r.centre_mm).attr("ravel")();
    d["radius_mm"] = r.radius_mm;
    d["radius_sigma_mm"] = r.radius_sigma_mm;
    d["centre_covariance_mm2"] = ToArray(r.centre_covariance_mm2);
    d["rms_mm"] = r.rms_mm;
    d["num_points"] = r.num_points;
    d["num_outliers"] = r.num_outliers;
    d["variance_factor"] = r.variance_factor;
    d["correlation_factor"] = r.correlation_factor;
    d["crlb_centre_sigma_mm"] = ToArray(r.crlb_centre_sigma_mm).attr("ravel")();
    d["crlb_radius_sigma_mm"] = r.crlb_radius_sigma_mm;
    out.append(d);
  }
  return out;
}

namespace {

py::dict DecodedToPython(const vision::DecodedCamera& d) {
  py::dict out;
  out["coordinate"] = MatToArray(d.coordinate);
  out["wrapped"] = MatToArray(d.wrapped);
  out["background"] = MatToArray(d.background);
  out["modulation"] = MatToArray(d.modulation);
  out["mask"] = MatToArray(d.mask);
  out["sigma_phase"] = MatToArray(d.sigma_phase);
  out["sigma_coordinate"] = MatToArray(d.sigma_coordinate);
  out["summary"] = JsonToPython(vision::DecodeSummaryToJson(d.summary));
  return out;
}

// Frames as cv::Mat headers over the arrays' buffers (the Python layer checked them: 2-D,
// C-contiguous, uint8 / uint16 / float32). The list keeps the arrays alive during the call.
std::vector<cv::Mat> FramesOf(const py::list& frames) {
  std::vector<cv::Mat> out;
  for (const py::handle& h : frames) {
    const py::array a = py::reinterpret_borrow<py::array>(h);
    const int type = a.dtype().is(py::dtype::of<std::uint8_t>())    ? CV_8UC1
                     : a.dtype().is(py::dtype::of<std::uint16_t>()) ? CV_16UC1
                                                                    : CV_32FC1;
    out.emplace_back(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), type, const_cast<void*>(a.data()),
                     static_cast<std::size_t>(a.strides(0)));
  }
  return out;
}

// The decode options the command line exposes, from the dict of the Python layer.
void ApplyDecodeOptions(const py::dict& o, vision::DecodeOptions* d) {
  if (o.contains("min_modulation")) d->min_modulation_fraction = o["min_modulation"].cast<double>();
  if (o.contains("sigma_intensity")) d->intensity_sigma_dn = o["sigma_intensity"].cast<double>();
  if (o.contains("no_nonlinearity")) d->correct_nonlinearity = !o["no_nonlinearity"].cast<bool>();
  if (o.contains("phase_filter")) d->coordinate_filter.radius_px = o["phase_filter"].cast<int>();
  if (o.contains("whole_residual_sigma")) d->noise_from_neighbours = !o["whole_residual_sigma"].cast<bool>();
}

using ScanHandle = std::shared_ptr<vision::ScanResult>;

// Runs `scan` without the GIL, with the Python progress callable; re-raises its error.
template <typename Scan>
ScanHandle RunScan(const py::dict& options, const py::object& progress, Scan scan) {
  vision::ScanOptions o = ScanOptionsOf(options);
  ProgressBridge bridge(progress);
  o.progress = bridge.Callback();
  auto r = std::make_shared<vision::ScanResult>();
  {
    py::gil_scoped_release release;
    *r = scan(o);
  }
  bridge.Rethrow();
  return r;
}

// A float32 view of `count` × `cols` values at `data`, kept alive by `owner`.
py::array View(const py::object& owner, const float* data, std::size_t count, py::ssize_t cols) {
  if (cols == 1) return py::array_t<float>({static_cast<py::ssize_t>(count)}, {sizeof(float)}, data, owner);
  return py::array_t<float>({static_cast<py::ssize_t>(count), cols},
                            {static_cast<py::ssize_t>(cols * sizeof(float)), static_cast<py::ssize_t>(sizeof(float))},
                            data, owner);
}

void BindStereoCalibration(py::module_& m) {
  using camera::CameraIntrinsics;
  using camera::StereoCalibration;
  auto intrinsics = [](const py::array_t<double, py::array::c_style | py::array::forcecast>& k,
                       const std::vector<double>& dist, int width, int height, const char* side,
                       camera::LensModel model = camera::LensModel::kPinhole5) {
    const std::string f = std::string(side) + "_K";
    if (k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3) throw InputError({"", 0, f}, "expected a 3x3 matrix");
    if (k.at(0, 1) != 0 || k.at(1, 0) != 0 || k.at(2, 0) != 0 || k.at(2, 1) != 0 || k.at(2, 2) != 1 ||
        !(k.at(0, 0) > 0) || !(k.at(1, 1) > 0) || !std::isfinite(k.at(0, 2)) || !std::isfinite(k.at(1, 2)) ||
        !std::isfinite(k.at(0, 0)) || !std::isfinite(k.at(1, 1)))
      throw InputError({"", 0, f}, "not a pinhole matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0");
    for (double v : dist)
      if (!std::isfinite(v)) throw InputError({"", 0, std::string(side) + "_distortion"}, "not finite");
    // OpenCV's coefficient vector of the camera's lens model (5 for the default model).
    CameraIntrinsics c;
    const std::string bad = dist.size() < 4 ? "expected 5 coefficients k1 k2 p1 p2 k3"
                                            : camera::DistortionFromVector(dist, model, &c.distortion);
    if (!bad.empty()) throw InputError({"", 0, std::string(side) + "_distortion"}, bad);
    c.fx = k.at(0, 0), c.fy = k.at(1, 1), c.cx = k.at(0, 2), c.cy = k.at(1, 2);
    c.width = width, c.height = height;
    return c;
  };
  auto distortion = [](const CameraIntrinsics& c) { return camera::DistortionVector(c.distortion); };
  // A changed copy is accepted only if the file reader accepts it (pinhole K, 5 distortion
  // coefficients, a rotation, positive sizes); InputError names the field otherwise.
  auto checked = [](const StereoCalibration& c) {
    return camera::ParseStereoCalibration(camera::StereoCalibrationText(c, true), "StereoCalibration");
  };
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  auto set_intrinsics = [intrinsics, checked](StereoCalibration& c, bool left, const Array* k,
                                              const std::vector<double>* dist) {
    StereoCalibration copy = c;
    CameraIntrinsics& cam = left ? copy.left : copy.right;
    const Array current = ToArray(cam.K());
    cam = intrinsics(k ? *k : current, dist ? *dist : camera::DistortionVector(cam.distortion), cam.width, cam.height,
                     left ? "left" : "right", cam.distortion.model);
    c = checked(copy);
  };
  py::class_<StereoCalibration>(m, "StereoCalibration")
      .def(py::init([intrinsics, checked](const Array& left_K, const std::vector<double>& left_distortion,
                                          const Array& right_K, const std::vector<double>& right_distortion,
                                          const Array& right_from_left, std::pair<int, int> image_size) {
             StereoCalibration c;
             c.left = intrinsics(left_K, left_distortion, image_size.first, image_size.second, "left");
             c.right = intrinsics(right_K, right_distortion, image_size.first, image_size.second, "right");
             if (right_from_left.ndim() != 2 || right_from_left.shape(0) != 4 || right_from_left.shape(1) != 4)
               throw InputError({"", 0, "right_from_left"}, "expected a 4x4 matrix");
             for (int i = 0; i < 4; ++i)
               for (int j = 0; j < 4; ++j) c.right_from_left.matrix()(i, j) = right_from_left.at(i, j);
             return checked(c);
           }),
           py::arg("left_K"), py::arg("left_distortion"), py::arg("right_K"), py::arg("right_distortion"),
           py::arg("right_from_left"), py::arg("image_size"))
      .def_static("read", &camera::ReadStereoCalibration, py::arg("path"))
      .def(
          "write", [](const StereoCalibration& c, const std::string& path) { camera::WriteStereoCalibration(path, c); },
          py::arg("path"))
      .def_property(
          "left_K", [](const StereoCalibration& c) { return ToArray(c.left.K()); },
          [set_intrinsics](StereoCalibration& c, const Array& k) { set_intrinsics(c, true, &k, nullptr); })
      .def_property(
          "right_K", [](const StereoCalibration& c) { return ToArray(c.right.K()); },
          [set_intrinsics](StereoCalibration& c, const Array& k) { set_intrinsics(c, false, &k, nullptr); })
      .def_property(
          "left_distortion", [distortion](const StereoCalibration& c) { return distortion(c.left); },
          [set_intrinsics](StereoCalibration& c, const std::vector<double>& d) {
            set_intrinsics(c, true, nullptr, &d);
          })
      .def_property(
          "right_distortion", [distortion](const StereoCalibration& c) { return distortion(c.right); },
          [set_intrinsics](StereoCalibration& c, const std::vector<double>& d) {
            set_intrinsics(c, false, nullptr, &d);
          })
      .def_property(
          "image_size", [](const StereoCalibration& c) { return std::make_pair(c.left.width, c.left.height); },
          [checked](StereoCalibration& c, std::pair<int, int> size) {
            StereoCalibration copy = c;
            copy.left.width = copy.right.width = size.first;
            copy.left.height = copy.right.height = size.second;
            c = checked(copy);
          })
      .def_property(
          "right_from_left", [](const StereoCalibration& c) { return ToArray(c.right_from_left.matrix()); },
          [checked](StereoCalibration& c, const Array& t) {
            if (t.ndim() != 2 || t.shape(0) != 4 || t.shape(1) != 4)
              throw InputError({"", 0, "right_from_left"}, "expected a 4x4 matrix");
            StereoCalibration copy = c;
            for (int i = 0; i < 4; ++i)
              for (int j = 0; j < 4; ++j) copy.right_from_left.matrix()(i, j) = t.at(i, j);
            c = checked(copy);
          })
      .def_readonly("rms_px", &StereoCalibration::rms_px)
      .def_readonly("parameter_std", &StereoCalibration::parameter_std)
      .def("__repr__", [](const StereoCalibration& c) {
        return "<ramtk.StereoCalibration " + std::to_string(c.left.width) + "x" + std::to_string(c.left.height) +
               ", baseline " + std::to_string(c.right_from_left.translation().norm()) + " mm>";
      });
}

void BindScanData(py::module_& m) {
  py::class_<vision::ScanResult, ScanHandle>(m, "ScanData")
      .def_property_readonly("points",
                             [](const py::object& self) {
                               const auto& c = self.cast<const vision::ScanResult&>().cloud;
                               return View(self, c.points_in_left.empty() ? nullptr : c.points_in_left[0].data(),
                                           c.size(), 3);
                             })
      .def_property_readonly("sigma_mm",
                             [](const py::object& self) {
                               const auto& c = self.cast<const vision::ScanResult&>().cloud;
                               return View(self, c.sigma_mm.data(), c.sigma_mm.size(), 1);
                             })
      .def_property_readonly("quality",
                             [](const py::object& self) {
                               const auto& c = self.cast<const vision::ScanResult&>().cloud;
                               return View(self, c.quality.data(), c.quality.size(), 1);
                             })
      .def_property_readonly("depth", [](const vision::ScanResult& r) { return MatToArray(r.depth); })
      .def_property_readonly("spheres", [](const vision::ScanResult& r) { return SpheresToPython(r.summary.spheres); })
      .def_property_readonly(
          "summary", [](const vision::ScanResult& r) { return JsonToPython(vision::ScanSummaryToJson(r.summary)); })
      .def_property_readonly(
          "termination",
          [](const vision::ScanResult& r) { return std::string(TerminationName(r.summary.termination)); })
      .def_property_readonly("report", [](const vision::ScanResult& r) { return r.summary.BriefReport(); })
      .def(
          "write",
          [](const vision::ScanResult& r, const std::string& out_dir, const std::string& set, bool force,
             bool html_report) {
            py::gil_scoped_release release;
            vision::ScanOutputWriter writer(out_dir, force, set);
            writer.Finish(r, html_report);
          },
          py::arg("out_dir"), py::arg("set"), py::arg("force"), py::arg("html_report"));
}

}  // namespace

// ScanOptions as `ramtk scan` builds them from its options (tools/vision_scan_command.cpp).
vision::ScanOptions ScanOptionsOf(const py::dict& o) {
  vision::ScanOptions s;
  if (o.contains("calibration")) s.calibration_path = o["calibration"].cast<std::string>();
  s.sphere.radius_mm = o["radius"].cast<double>();
  s.sphere.fix_radius = o["fix_radius"].cast<bool>();
  s.sphere.max_spheres = o["spheres"].cast<int>();
  s.match.min_depth_mm = o["min_depth"].cast<double>();
  s.match.max_depth_mm = o["max_depth"].cast<double>();
  ApplyDecodeOptions(o, &s.decode);
  s.match.lr_sigma_factor = o["lr_sigma_factor"].cast<double>();
  s.match.noise_bias_term = o["noise_term"].cast<bool>();
  s.match.kernel_estimate = o["kernel_estimate"].cast<std::string>() == "auto"
                                ? vision::StereoMatchOptions::KernelEstimate::kAuto
                                : vision::StereoMatchOptions::KernelEstimate::kOff;
  s.roi = vision::ParseScanRoi(o["roi"].cast<std::string>());
  s.roi.margin_mm = o["roi_margin"].cast<double>();
  s.roi.coarse_stride = o["roi_stride"].cast<int>();
  s.read_rows_on_demand = !o["load_whole_frames"].cast<bool>();
  ThrowIfInvalid(s.Validate(), "ScanOptions");
  return s;
}

void BindVision(py::module_& m) {
  BindStereoCalibration(m);
  BindScanData(m);
  m.def("read_image", [](const std::string& path) {
    // Any single-channel image OpenCV reads as stored: 8/16-bit camera frames, the float TIFF /
    // EXR maps of `ramtk decode` and of the simulator's truth.
    RequireRegularFile(path);  // a FIFO or a device would block or never end
    cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
    if (img.empty()) throw InputError({path, 0, ""}, "cannot read the image");
    if (img.channels() != 1) throw InputError({path, 0, ""}, "expected a single-channel image");
    return MatToArray(img);
  });
  m.def("read_manifest", [](const std::string& path) {
    const vision::FringeManifest mf = vision::ReadFringeManifest(path);
    py::dict d = JsonToPython(vision::FringeManifestToJson(mf));
    py::dict resolved;
    for (const auto& [camera, files] : mf.cameras) {
      std::vector<std::string> paths;
      for (const std::string& f : files) paths.push_back(mf.Resolve(f));
      resolved[py::str(camera)] = paths;
    }
    d["resolved_images"] = resolved;
    return d;
  });
  m.def("decode", [](const std::string& manifest, const std::string& camera, const py::dict& options) {
    vision::DecodeOptions o;
    ApplyDecodeOptions(options, &o);
    ThrowIfInvalid(o.Validate(), "DecodeOptions");
    vision::DecodedCamera d;
    {
      py::gil_scoped_release release;
      d = vision::DecodeCamera(vision::ReadFringeManifest(manifest), camera, o);
    }
    return DecodedToPython(d);
  });
  // `sequence_text`: the manifest's JSON (its image paths are not read); `sequence_path` names it.
  m.def("decode_frames", [](const py::list& frames, const std::string& sequence_text, const std::string& sequence_path,
                            double full_scale, const std::string& camera, const py::dict& options) {
    vision::DecodeOptions o;
    ApplyDecodeOptions(options, &o);
    ThrowIfInvalid(o.Validate(), "DecodeOptions");
    const vision::FringeManifest mf = vision::ParseFringeManifest(sequence_text, sequence_path);
    const std::vector<cv::Mat> mats = FramesOf(frames);
    vision::DecodedCamera d;
    {
      py::gil_scoped_release release;
      d = vision::DecodeFrames(mf, mats, full_scale, o, camera);
    }
    return DecodedToPython(d);
  });
  m.def("scan", [](const std::string& manifest, const py::dict& options, const py::object& progress) {
    return RunScan(options, progress, [&](const vision::ScanOptions& o) { return vision::ScanFringeSet(manifest, o); });
  });
  m.def("scan_frames",
        [](const py::list& left, const py::list& right, const camera::StereoCalibration& calibration,
           const std::string& calibration_path, const std::string& sequence_text, const std::string& sequence_path,
           double full_scale, const py::dict& options, const py::object& progress) {
          const vision::FringeManifest mf = vision::ParseFringeManifest(sequence_text, sequence_path);
          const std::vector<cv::Mat> l = FramesOf(left), r = FramesOf(right);
          camera::StereoCalibration named = calibration;
          named.source_path = calibration_path;
          return RunScan(options, progress, [&](const vision::ScanOptions& o) {
            return vision::ScanFrames(mf, named, l, r, full_scale, o);
          });
        });
  m.def("fit_sphere",
        [](const py::array_t<double, py::array::c_style | py::array::forcecast>& points, const py::object& sigma,
           double radius, bool fix_radius, int spheres, std::uint64_t seed, int min_points) {
          std::vector<Eigen::Vector3f> pts(static_cast<std::size_t>(points.shape(0)));
          auto p = points.unchecked<2>();
          for (py::ssize_t i = 0; i < points.shape(0); ++i) pts[i] = Eigen::Vector3f(p(i, 0), p(i, 1), p(i, 2));
          std::vector<float> sig;
          if (!sigma.is_none()) {
            const auto s = sigma.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
            for (py::ssize_t i = 0; i < s.shape(0); ++i) sig.push_back(static_cast<float>(s.at(i)));
          }
          vision::SphereFitOptions o;
          o.radius_mm = radius;
          o.fix_radius = fix_radius;
          o.max_spheres = spheres;
          o.seed = seed;
          o.min_points = min_points;
          ThrowIfInvalid(o.Validate(), "SphereFitOptions");
          vision::SphereFitSummary s;
          {
            py::gil_scoped_release release;
            s = vision::FindSpheres(pts, sig, o);
          }
          return SpheresToPython(s);
        });
  m.def("simulate_fringe",
        [](const std::string& out, const std::string& preset, std::uint64_t seed, bool noise, int supersampling,
           bool force, const std::string& frame_format, const py::object& progress) {
          vision::FringeSimulationConfig config = vision::MakeFringePreset(preset);
          config.seed = seed;
          config.sensor.noise = noise;
          config.supersampling = supersampling;
          config.frame_format = frame_format;
          ProgressBridge bridge(progress);
          vision::FringeSimulationSummary s;
          {
            py::gil_scoped_release release;
            s = vision::SimulateFringeSet(config, out, force, bridge.Callback());
          }
          bridge.Rethrow();
          py::dict d;
          d["out_dir"] = s.out_dir;
          d["frames"] = s.frames;
          d["width"] = s.width;
          d["height"] = s.height;
          d["manifest"] = out + "/manifest.json";
          d["truth"] = out + "/truth/truth.json";
          return d;
        });
  m.def("read_truth_spheres", [](const std::string& path) {
    py::list out;
    for (const vision::Sphere& s : vision::ReadTruthSpheres(path)) {
      py::dict d;
      d["name"] = s.name;
      d["centre_mm"] = ToArray(s.centre_in_left).attr("ravel")();
      d["radius_mm"] = s.radius;
      out.append(d);
    }
    return out;
  });
}

}  // namespace ramtk::python
