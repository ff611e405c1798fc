// Fringe decoding, the scan pipeline, sphere fitting, stereo calibration files and the fringe
// simulator. Images come back as numpy arrays that share the C++ buffers (no copy); options are
// keyword arguments with the C++ defaults; long calls release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <opencv2/imgcodecs.hpp>

#include "numpy_convert.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/vision/decode.h"
#include "ramtk/vision/fringe_simulator.h"
#include "ramtk/vision/manifest.h"
#include "ramtk/vision/scan.h"
#include "ramtk/vision/sphere_fit.h"

namespace ramtk::python {
namespace {

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
    out.append(d);
  }
  return out;
}

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

}  // namespace

void BindVision(py::module_& m) {
  m.def(
      "read_image",
      [](const std::string& path) {
        // Any single-channel image OpenCV reads as stored: 8/16-bit camera frames, the float TIFF
        // / EXR maps of `ramtk decode` and of the simulator's truth.
        RequireRegularFile(path);  // a FIFO or a device would block or never end
        cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
        if (img.empty()) throw InputError({path, 0, ""}, "cannot read the image");
        if (img.channels() != 1) throw InputError({path, 0, ""}, "expected a single-channel image");
        return MatToArray(img);
      },
      py::arg("path"), "A single-channel image as stored (uint8, uint16 or float32 array)");

  m.def(
      "read_manifest",
      [](const std::string& path) {
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
      },
      py::arg("path"), "A fringe-set manifest as a dict (validated), plus each camera's image paths resolved");

  m.def(
      "decode",
      [](const std::string& manifest, const std::string& camera, double min_modulation_fraction,
         double intensity_sigma_dn, bool correct_nonlinearity, bool noise_from_neighbours) {
        vision::DecodeOptions o;
        o.min_modulation_fraction = min_modulation_fraction;
        o.intensity_sigma_dn = intensity_sigma_dn;
        o.correct_nonlinearity = correct_nonlinearity;
        o.noise_from_neighbours = noise_from_neighbours;
        ThrowIfInvalid(o.Validate(), "DecodeOptions");
        vision::DecodedCamera d;
        {
          py::gil_scoped_release release;
          d = vision::DecodeCamera(vision::ReadFringeManifest(manifest), camera, o);
        }
        return DecodedToPython(d);
      },
      py::arg("manifest"), py::arg("camera") = "left",
      py::arg("min_modulation_fraction") = vision::DecodeOptions{}.min_modulation_fraction,
      py::arg("intensity_sigma_dn") = vision::DecodeOptions{}.intensity_sigma_dn,
      py::arg("correct_nonlinearity") = vision::DecodeOptions{}.correct_nonlinearity,
      py::arg("noise_from_neighbours") = vision::DecodeOptions{}.noise_from_neighbours,
      "Decodes one camera of a fringe set: dict of numpy arrays (coordinate in projector px, NaN invalid; wrapped, "
      "background, modulation in DN; mask 0/255; sigma_phase rad; sigma_coordinate px) and 'summary'");

  m.def(
      "scan",
      [](const std::string& manifest, const std::string& calibration_path, double radius_mm, bool fix_radius,
         int max_spheres, double min_depth_mm, double max_depth_mm, const std::string& roi, double roi_margin_mm) {
        vision::ScanOptions o;
        o.roi = vision::ParseScanRoi(roi);
        o.roi.margin_mm = roi_margin_mm;
        o.calibration_path = calibration_path;
        o.sphere.radius_mm = radius_mm;
        o.sphere.fix_radius = fix_radius;
        o.sphere.max_spheres = max_spheres;
        o.match.min_depth_mm = min_depth_mm;
        o.match.max_depth_mm = max_depth_mm;
        ThrowIfInvalid(o.Validate(), "ScanOptions");
        vision::ScanResult r;
        {
          py::gil_scoped_release release;
          r = vision::ScanFringeSet(manifest, o);
        }
        const vision::PointCloud& c = r.cloud;
        py::array_t<double> points({static_cast<py::ssize_t>(c.size()), py::ssize_t{5}});
        auto p = points.mutable_unchecked<2>();
        for (std::size_t i = 0; i < c.size(); ++i) {
          for (int k = 0; k < 3; ++k) p(i, k) = c.points_in_left[i][k];
          p(i, 3) = c.sigma_mm.empty() ? std::nan("") : c.sigma_mm[i];
          p(i, 4) = c.quality.empty() ? std::nan("") : c.quality[i];
        }
        py::dict out;
        out["points"] = points;
        out["depth"] = MatToArray(r.depth);
        out["spheres"] = SpheresToPython(r.summary.spheres);
        out["summary"] = JsonToPython(vision::ScanSummaryToJson(r.summary));
        return out;
      },
      py::arg("manifest"), py::arg("calibration_path") = vision::ScanOptions{}.calibration_path,
      py::arg("radius_mm") = vision::ScanOptions{}.sphere.radius_mm,
      py::arg("fix_radius") = vision::ScanOptions{}.sphere.fix_radius,
      py::arg("max_spheres") = vision::ScanOptions{}.sphere.max_spheres,
      py::arg("min_depth_mm") = vision::ScanOptions{}.match.min_depth_mm,
      py::arg("max_depth_mm") = vision::ScanOptions{}.match.max_depth_mm, py::arg("roi") = "full",
      py::arg("roi_margin_mm") = vision::ScanRoiOptions{}.margin_mm,
      "Scans a stereo fringe set: 'points' N×5 (x, y, z mm in the left-camera frame, sigma mm, quality), 'depth' "
      "(z per left pixel, NaN none), 'spheres' (centre, radius, centre covariance), 'summary'. roi: 'full', "
      "'auto' (a coarse pass finds the ball, then only windows around it are decoded and matched) or 'X,Y,Z' (a "
      "predicted ball_in_left_camera, mm); summary['roi'] gives the windows");

  m.def(
      "fit_sphere",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& points, py::object sigma,
         double radius_mm, bool fix_radius, int max_spheres, std::uint64_t seed, int min_points) {
        if (points.ndim() != 2 || points.shape(1) != 3) throw InputError({"", 0, "points"}, "expected an N×3 array");
        std::vector<Eigen::Vector3f> pts(static_cast<std::size_t>(points.shape(0)));
        auto p = points.unchecked<2>();
        for (py::ssize_t i = 0; i < points.shape(0); ++i) pts[i] = Eigen::Vector3f(p(i, 0), p(i, 1), p(i, 2));
        std::vector<float> sig;
        if (!sigma.is_none()) {
          const auto s = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(sigma);
          if (!s || s.ndim() != 1 || s.shape(0) != points.shape(0))
            throw InputError({"", 0, "sigma"}, "expected one sigma per point");
          for (py::ssize_t i = 0; i < s.shape(0); ++i) sig.push_back(static_cast<float>(s.at(i)));
        }
        vision::SphereFitOptions o;
        o.radius_mm = radius_mm;
        o.fix_radius = fix_radius;
        o.max_spheres = max_spheres;
        o.seed = seed;
        o.min_points = min_points;
        ThrowIfInvalid(o.Validate(), "SphereFitOptions");
        vision::SphereFitSummary s;
        {
          py::gil_scoped_release release;
          s = vision::FindSpheres(pts, sig, o);
        }
        return SpheresToPython(s);
      },
      py::arg("points"), py::arg("sigma") = py::none(), py::arg("radius_mm") = vision::SphereFitOptions{}.radius_mm,
      py::arg("fix_radius") = vision::SphereFitOptions{}.fix_radius,
      py::arg("max_spheres") = vision::SphereFitOptions{}.max_spheres,
      py::arg("seed") = vision::SphereFitOptions{}.seed, py::arg("min_points") = vision::SphereFitOptions{}.min_points,
      "Finds up to `max_spheres` spheres in an N×3 cloud (mm): list of dicts with centre_mm, radius_mm, "
      "centre_covariance_mm2, rms_mm, num_points");

  py::class_<camera::StereoCalibration>(m, "StereoCalibration",
                                        "A stereo calibration (the file of `ramtk calib cameras`, OpenCV YAML / JSON)")
      .def_static("read", &camera::ReadStereoCalibration, py::arg("path"))
      .def(
          "write",
          [](const camera::StereoCalibration& c, const std::string& path) { camera::WriteStereoCalibration(path, c); },
          py::arg("path"), "Writes YAML, or JSON when the path ends in .json (atomically)")
      .def_property_readonly("left_K", [](const camera::StereoCalibration& c) { return ToArray(c.left.K()); })
      .def_property_readonly("right_K", [](const camera::StereoCalibration& c) { return ToArray(c.right.K()); })
      .def_property_readonly(
          "image_size", [](const camera::StereoCalibration& c) { return std::make_pair(c.left.width, c.left.height); })
      .def_property_readonly(
          "right_from_left", [](const camera::StereoCalibration& c) { return ToArray(c.right_from_left.matrix()); },
          "4×4, translation in mm")
      .def_readonly("rms_px", &camera::StereoCalibration::rms_px)
      .def_readonly("parameter_std", &camera::StereoCalibration::parameter_std);

  m.def(
      "simulate_fringe",
      [](const std::string& out, const std::string& preset, std::uint64_t seed, bool noise, int supersampling,
         bool force, const std::string& frame_format) {
        vision::FringeSimulationConfig config = vision::MakeFringePreset(preset);
        config.seed = seed;
        config.sensor.noise = noise;
        config.supersampling = supersampling;
        config.frame_format = frame_format;
        vision::FringeSimulationSummary s;
        {
          py::gil_scoped_release release;
          s = vision::SimulateFringeSet(config, out, force, {});
        }
        py::dict d;
        d["out_dir"] = s.out_dir;
        d["frames"] = s.frames;
        d["width"] = s.width;
        d["height"] = s.height;
        d["manifest"] = out + "/manifest.json";
        d["truth"] = out + "/truth/truth.json";
        return d;
      },
      py::arg("out"), py::arg("preset") = "small", py::arg("seed") = 1, py::arg("noise") = true,
      py::arg("supersampling") = 4, py::arg("force") = false,
      py::arg("frame_format") = vision::FringeSimulationConfig{}.frame_format,
      "Renders a stereo fringe set of the ball (ramtk simulate fringe) into `out`; frame_format png or bmp "
      "(8-bit uncompressed, read by rows under scan's roi)");

  m.def(
      "read_truth_spheres",
      [](const std::string& path) {
        py::list out;
        for (const vision::Sphere& s : vision::ReadTruthSpheres(path)) {
          py::dict d;
          d["name"] = s.name;
          d["centre_mm"] = ToArray(s.centre_in_left).attr("ravel")();
          d["radius_mm"] = s.radius;
          out.append(d);
        }
        return out;
      },
      py::arg("path"), "The true spheres of a simulated set (truth/truth.json)");
}

}  // namespace ramtk::python
