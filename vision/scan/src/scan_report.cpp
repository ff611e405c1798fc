#include "ramtk/vision/scan/scan_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "ramtk/core/csv.h"

namespace ramtk::vision {
namespace {

std::string Fmt(double v, int digits = 4) { return FormatSignificant(v, digits); }

}  // namespace

report::Figure SphereResidualFigure(const ScanResult& result, int k, size_t max_points) {
  const SphereResult& s = result.summary.spheres.spheres.at(k);
  const PointCloud& cloud = result.cloud;
  report::Series dots, mean;
  dots.label = "inliers";
  mean.label = "mean per 2°";
  mean.style = report::SeriesStyle::kLinesPoints;
  const size_t n = s.inlier_indices.size();
  const size_t step = std::max<size_t>(1, (n + max_points - 1) / std::max<size_t>(1, max_points));
  constexpr int kBins = 45;  // 0..90° in 2° bins
  std::vector<double> sum(kBins, 0.0);
  std::vector<long> count(kBins, 0);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = cloud.points_in_left[s.inlier_indices[i]].cast<double>();
    const Eigen::Vector3d radial = p - s.centre_mm;
    const double r = radial.norm();
    if (r <= 0) continue;
    // Angle between the outward normal and the direction back to the camera (origin).
    const double c = std::clamp(radial.dot(-p) / (r * p.norm()), -1.0, 1.0);
    const double angle = std::acos(c) * 180.0 / M_PI;
    const double res_um = (r - s.radius_mm) * 1000.0;
    const int b = std::clamp(static_cast<int>(angle / 2.0), 0, kBins - 1);
    sum[b] += res_um, ++count[b];
    if (i % step == 0) dots.x.push_back(angle), dots.y.push_back(res_um);
  }
  for (int b = 0; b < kBins; ++b)
    if (count[b] >= 20) mean.x.push_back(2.0 * b + 1.0), mean.y.push_back(sum[b] / count[b]);
  report::Figure f;
  f.id = "sphere" + std::to_string(k) + "_residual";
  f.caption =
      "Distance of each inlier to the fitted sphere against the angle between the surface normal and the "
      "line of sight (0° faces the camera); grey band ± the median predicted point σ. A trend towards the "
      "limb is a view-angle bias.";
  report::Panel p;
  p.title = "sphere " + std::to_string(k + 1) + ": radial residual vs view angle";
  p.x_label = "angle between normal and line of sight (deg)";
  p.y_label = "radial residual (µm)";
  p.series = {dots, mean};
  p.zero_band = result.summary.triangulation.median_sigma_mm * 1000.0;
  p.zero_band_label = "± median point σ";
  f.panels.push_back(p);
  return f;
}

report::HtmlReport ScanReport(const ScanResult& result, const std::string& depth_png) {
  const ScanSummary& s = result.summary;
  report::HtmlReport html("Scan: " + (s.set.empty() ? std::string("in-memory set") : s.set));
  html.Paragraph(s.BriefReport());
  html.KeyValues(
      {{"set", s.set},
       {"calibration", s.calibration},
       {"image size (px)", std::to_string(s.width) + " × " + std::to_string(s.height)},
       {"termination", s.message},
       {"points", std::to_string(s.triangulation.points)},
       {"median point σ (µm)", FormatFixed(s.triangulation.median_sigma_mm * 1000.0, 2)},
       {"depth range (mm)",
        FormatFixed(s.triangulation.depth_min_mm, 1) + " – " + FormatFixed(s.triangulation.depth_max_mm, 1)},
       {"frame", kScanFrame},
       {"calibration RMS (px)",
        std::isfinite(s.calibration_rms_px) ? FormatFixed(s.calibration_rms_px, 4) : "not in the file"},
       {"calibration σ", s.calibration_parameter_std.empty() ? "not in the file"
                                                             : std::to_string(s.calibration_parameter_std.size()) +
                                                                   " parameter standard deviations (summary.json)"}});

  html.Section("Spheres");
  if (s.spheres.spheres.empty()) {
    html.Paragraph("No sphere found: " + s.spheres.no_sphere_reason);
    if (!result.cloud.points_in_left.empty()) {
      report::Cloud3d c;
      c.title = "all points (subsampled)";
      c.colour_label = "z (mm)";
      c.diverging = false;
      c.max_points = 20000;
      for (const Eigen::Vector3f& p : result.cloud.points_in_left) {
        c.xyz.insert(c.xyz.end(), {p.x(), p.y(), p.z()});
        c.colour_value.push_back(p.z());
      }
      html.AddCloud("cloud", c, "Drag to rotate; colour: depth z (mm).");
    }
  } else {
    std::vector<std::vector<std::string>> rows;
    for (size_t k = 0; k < s.spheres.spheres.size(); ++k) {
      const SphereResult& r = s.spheres.spheres[k];
      const Eigen::Vector3d sig = r.CentreSigma() * 1000.0, bound = r.crlb_centre_sigma_mm * 1000.0;
      const std::string crlb = bound.minCoeff() > 0 ? FormatFixed(bound.x(), 2) + " / " + FormatFixed(bound.y(), 2) +
                                                          " / " + FormatFixed(bound.z(), 2)
                                                    : "—";
      rows.push_back({std::to_string(k + 1), FormatFixed(r.centre_mm.x(), 4), FormatFixed(r.centre_mm.y(), 4),
                      FormatFixed(r.centre_mm.z(), 4), FormatFixed(sig.x(), 2), FormatFixed(sig.y(), 2),
                      FormatFixed(sig.z(), 2), crlb, FormatFixed(r.radius_mm, 4), FormatFixed(r.rms_mm * 1000.0, 2),
                      std::to_string(r.num_points), std::to_string(r.num_outliers), Fmt(r.variance_factor, 3)});
    }
    html.Table({"sphere", "x (mm)", "y (mm)", "z (mm)", "σx (µm)", "σy (µm)", "σz (µm)",
                "Cramér–Rao bound x / y / z (µm)", "radius (mm)", "RMS (µm)", "inliers", "outliers", "χ²/(n−p)"},
               rows);
    for (size_t k = 0; k < s.spheres.spheres.size(); ++k) {
      const SphereResult& r = s.spheres.spheres[k];
      // Points near the sphere, coloured by their radial residual.
      report::Cloud3d c;
      c.title = "sphere " + std::to_string(k + 1) + ": points within 3 mm of the fitted surface";
      c.colour_label = "radial residual (µm)";
      c.sphere_radius = r.radius_mm;
      for (int a = 0; a < 3; ++a) c.sphere_centre[a] = r.centre_mm[a];
      c.max_points = 20000;
      for (const Eigen::Vector3f& p : result.cloud.points_in_left) {
        const double d = (p.cast<double>() - r.centre_mm).norm() - r.radius_mm;
        if (std::abs(d) > 3.0) continue;
        c.xyz.insert(c.xyz.end(), {p.x(), p.y(), p.z()});
        c.colour_value.push_back(static_cast<float>(std::clamp(d * 1000.0, -200.0, 200.0)));
      }
      if (!c.xyz.empty())
        html.AddCloud("sphere" + std::to_string(k) + "_cloud", c,
                      "Drag to rotate. Colour: distance to the fitted sphere (µm, clipped at ±200); grey: the fit.");
      html.AddFigure(SphereResidualFigure(result, static_cast<int>(k)));
    }
  }

  html.Section("Stages");
  std::vector<std::vector<std::string>> stage_rows;
  for (const DecodeSummary* d : {&s.left, &s.right})
    stage_rows.push_back({"decode " + d->camera, FormatFixed(d == &s.left ? s.decode_s : 0.0, 2),
                          FormatFixed(100.0 * d->valid_fraction, 1) + "% valid pixels",
                          "B median " + FormatFixed(d->median_modulation_dn, 1) + " DN, σφ median " +
                              Fmt(d->median_sigma_phase_rad, 3) + " rad, σI random " +
                              Fmt(d->sigma_intensity_random_dn, 3) + " DN"});
  stage_rows.push_back({"match", FormatFixed(s.match_s, 2),
                        std::to_string(s.match.matched) + " of " + std::to_string(s.match.left_valid),
                        "rejected: noisy " + std::to_string(s.match.rejected_noisy) + ", no match " +
                            std::to_string(s.match.rejected_no_match) + ", left–right " +
                            std::to_string(s.match.rejected_lr) + ", no back match " +
                            std::to_string(s.match.rejected_no_back_match) + "; median σ " +
                            Fmt(s.match.median_sigma_px, 3) + " px"});
  stage_rows.push_back({"triangulate", FormatFixed(s.triangulate_s, 2),
                        std::to_string(s.triangulation.points) + " points",
                        "median σ " + FormatFixed(s.triangulation.median_sigma_mm * 1000.0, 2) + " µm"});
  if (s.tri_view)
    stage_rows.push_back({"tri-view", "", std::to_string(s.projector_points) + " of " +
                                              std::to_string(s.projector.coded_pixels),
                          std::to_string(s.stereo_points) + " stereo + " + std::to_string(s.projector_points) +
                              " left camera–projector points (the left pixels without a stereo point); median σ " +
                              FormatFixed(s.projector.median_sigma_mm * 1000.0, 2) + " µm"});
  stage_rows.push_back({"fit", FormatFixed(s.fit_s, 2), std::to_string(s.spheres.spheres.size()) + " sphere(s)", ""});
  html.Table({"stage", "wall time (s)", "count", "figures"}, stage_rows);
  html.Paragraph("The decode time covers both cameras.");
  if (!depth_png.empty() && std::filesystem::exists(depth_png)) {
    html.Section("Depth");
    html.AddImage("depth", depth_png, "Depth z per left pixel (near = red, far = blue, black = no point).");
  }
  html.Section("Files");
  html.Links({{"point cloud (PLY, left-camera frame, mm)", "cloud.ply"},
              {"spheres (JSON)", "spheres.json"},
              {"summary (JSON)", "summary.json"},
              {"depth picture (PNG)", "depth.png"}});
  return html;
}

report::HtmlReport ScanBatchReport(const std::vector<ScanBatchRow>& rows, const std::string& out_dir) {
  namespace fs = std::filesystem;
  report::HtmlReport html("Scan batch: " + std::to_string(rows.size()) + " sets");
  int ok = 0, none = 0, bad = 0;
  for (const ScanBatchRow& r : rows) (r.status == "ok" ? ok : r.status == "error" ? bad : none)++;
  html.KeyValues({{"sets", std::to_string(rows.size())},
                  {"with a sphere", std::to_string(ok)},
                  {"without a sphere", std::to_string(none)},
                  {"errors", std::to_string(bad)},
                  {"folder", out_dir}});
  report::Series sx, sy, sz, rms, pts, secs;
  sx.label = "σx", sy.label = "σy", sz.label = "σz", rms.label = "fit RMS";
  pts.label = "points", secs.label = "wall time";
  for (auto* s : {&sx, &sy, &sz, &rms, &pts, &secs}) s->style = report::SeriesStyle::kLinesPoints;
  std::vector<std::vector<std::string>> table;
  for (size_t i = 0; i < rows.size(); ++i) {
    const ScanBatchRow& r = rows[i];
    const double x = static_cast<double>(i + 1);
    std::vector<std::string> row = {std::to_string(i + 1), r.set, r.status};
    if (r.has_sphere) {
      const Eigen::Vector3d sig = r.sphere.CentreSigma() * 1000.0;
      sx.x.push_back(x), sx.y.push_back(sig.x());
      sy.x.push_back(x), sy.y.push_back(sig.y());
      sz.x.push_back(x), sz.y.push_back(sig.z());
      rms.x.push_back(x), rms.y.push_back(r.sphere.rms_mm * 1000.0);
      row.insert(row.end(), {FormatFixed(r.sphere.centre_mm.x(), 4), FormatFixed(r.sphere.centre_mm.y(), 4),
                             FormatFixed(r.sphere.centre_mm.z(), 4), FormatFixed(sig.norm(), 2),
                             FormatFixed(r.sphere.radius_mm, 4)});
    } else {
      row.insert(row.end(), {"", "", "", "", ""});
    }
    pts.x.push_back(x), pts.y.push_back(static_cast<double>(r.points));
    secs.x.push_back(x), secs.y.push_back(r.seconds);
    row.push_back(std::to_string(r.points));
    row.push_back(FormatFixed(r.seconds, 2));
    row.push_back(r.message);
    table.push_back(row);
  }
  html.Section("Sets");
  html.Table({"#", "set", "status", "x (mm)", "y (mm)", "z (mm)", "|σ centre| (µm)", "radius (mm)", "points",
              "wall time (s)", "message"},
             table);
  if (ok > 0) {
    report::Figure f;
    f.id = "batch_centres";
    f.caption = "Per set: the centre's predicted standard deviation along x, y, z and the RMS of the sphere fit.";
    report::Panel a, b;
    a.title = "centre σ per set", a.x_label = "set number", a.y_label = "σ (µm)", a.series = {sx, sy, sz};
    b.title = "sphere fit RMS per set", b.x_label = "set number", b.y_label = "RMS (µm)", b.series = {rms};
    f.panels = {a, b};
    html.AddFigure(f);
  }
  report::Figure g;
  g.id = "batch_work";
  g.caption = "Per set: the number of triangulated points and the wall time of the scan.";
  report::Panel c, d;
  c.title = "points per set", c.x_label = "set number", c.y_label = "points", c.series = {pts};
  d.title = "wall time per set", d.x_label = "set number", d.y_label = "time (s)", d.series = {secs};
  g.panels = {c, d};
  html.AddFigure(g);
  html.Section("Files");
  std::vector<std::pair<std::string, std::string>> links;
  for (const ScanBatchRow& r : rows)
    if (!r.out_dir.empty()) {
      std::error_code ec;
      const fs::path rel = fs::relative(r.out_dir, out_dir, ec);
      links.push_back({r.set, ec ? r.out_dir : rel.string() + "/summary.json"});
    }
  html.Links(links);
  return html;
}

}  // namespace ramtk::vision
