// ramtk scan: fringe set + stereo calibration -> point cloud (PLY), sphere JSON, depth preview.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "test_hooks.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/scan/scan_batch.h"
#include "ramtk/vision/scan/scan_output_formats.h"
#include "ramtk/vision/scan/scan_report.h"

namespace ramtk::tools {
namespace {

struct ScanCommandOptions {
  std::string set;                            // fringe set manifest
  std::string batch;                          // list of manifests
  std::string calib;                          // stereo calibration (overrides the manifest's)
  std::string out = "scan_out";               // output folder
  std::string truth;                          // simulator truth.json for the error report
  double radius = 19.05;                      // sphere radius prior, mm
  bool fix_radius = false;                    // fit the centre only
  int spheres = 1;                            // spheres to look for
  double min_depth = 100, max_depth = 10000;  // epipolar search range, mm
  int jobs = 2;                               // sets in parallel (--batch)
  bool force = false;                         // replace existing outputs
  bool resume = false;                        // --batch: keep the sets an earlier run finished
  bool quiet = false;                         // no progress bar; a batch prints only its totals
  TestHooks hooks;                            // from RAMTK_TEST_HOOKS (test_hooks.h), no flag
  bool no_nonlinearity = false;               // skip the projector-nonlinearity correction
  bool whole_residual_sigma = false;          // sigma_I = the whole fit residual (no random/ripple split)
  int phase_filter = 0;                       // coordinate filter radius (px), 0 = off
  double lr_sigma_factor = vision::StereoMatchOptions{}.lr_sigma_factor;
  std::string kernel_estimate = "off";   // a camera without a stated sampling kernel: auto (estimated) or off
  bool ray_plane = false;                 // camera–projector sets with both directions: ray–plane only
  bool no_noise_term = false;             // matches without the noise's second-order term
  std::string modulation_rule = "sigma";  // weak-fringe rejection: sigma or fixed (DecodeOptions)
  double max_order_error = vision::DecodeOptions{}.max_order_error_probability;  // sigma rule's epsilon
  std::string shard;                                       // "K/N": scan only shard K of N of the batch
  bool report = false;                                     // also write report.html
  std::string roi = "full";                                // full, auto, or a predicted centre X,Y,Z (mm)
  double roi_margin = vision::ScanRoiOptions{}.margin_mm;  // mm added to the ball radius for the window
  int roi_stride = 0;                                      // coarse pass stride (0 = automatic)
  bool load_whole_frames = false;                          // --roi: load frames whole, not by rows
  bool tri_view = false;                                   // the projector as a third view
  std::string projector_calib;                             // tri-view's projector calibration
};

// The options that change a set's results (row.csv of each batch set; --resume compares them).
// --jobs, --quiet, --report and --load-whole-frames do not change results.
vision::ScanResultSettings ResultSettings(const ScanCommandOptions& o) {
  vision::ScanResultSettings s;
  s.calib = o.calib;
  s.radius = o.radius;
  s.fix_radius = o.fix_radius;
  s.spheres = o.spheres;
  s.min_depth = o.min_depth;
  s.max_depth = o.max_depth;
  s.reference_decode = o.hooks.reference_decode;
  s.full_search = o.hooks.full_search;
  s.curve_back_pass = o.hooks.curve_back_pass;
  s.no_nonlinearity = o.no_nonlinearity;
  s.whole_residual_sigma = o.whole_residual_sigma;
  s.phase_filter = o.phase_filter;
  s.lr_sigma_factor = o.lr_sigma_factor;
  s.kernel_estimate = o.kernel_estimate;
  s.modulation_rule = o.modulation_rule;
  s.ray_plane = o.ray_plane;
  s.no_noise_term = o.no_noise_term;
  s.max_order_error = o.max_order_error;
  s.roi = o.roi;
  s.roi_margin = o.roi_margin;
  s.roi_stride = o.roi_stride;
  s.tri_view = o.tri_view;
  s.projector_calib = o.projector_calib;
  return s;
}

// Without --force or --resume a batch changes nothing that an earlier run wrote: it refuses up
// front, before any set is scanned, when its results file or one of its set folders exists.
void RefuseToReplaceEarlierResults(const std::string& results, const std::vector<std::string>& sets,
                                   const std::vector<std::size_t>& positions, const std::string& out) {
  const std::string how = ": pass --resume to keep the sets it finished, or --force to scan every set again";
  std::error_code ec;
  if (std::filesystem::exists(results, ec)) throw InputError({results, 0, "--out"}, "exists" + how);
  for (std::size_t p : positions) {
    const std::string dir = vision::ScanBatchSetFolder(out, p, sets[p]);
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_empty(dir, ec))
      throw InputError({dir, 0, "--out"}, "exists (a set folder of an earlier run)" + how);
  }
}

// The sampling kernel the match's terms used: stated, or estimated (and whether applied).
std::string SamplingKernelLine(const vision::KernelVarianceEstimate& k) {
  char line[256];
  if (k.status == "stated") {
    std::snprintf(line, sizeof line, "sampling kernel: stated, variance %.4f / %.4f px^2 (left / right)", k.left_px2,
                  k.right_px2);
  } else if (std::isfinite(k.variance_px2)) {
    std::snprintf(line, sizeof line,
                  "sampling kernel: estimated variance %.4f +- %.4f px^2 over %ld px (leverage %.1f), %s",
                  k.variance_px2, k.sigma_px2, k.pixels, k.leverage, k.status.c_str());
  } else {
    std::snprintf(line, sizeof line, "sampling kernel: not estimated (%s)", k.status.c_str());
  }
  return line;
}

int RunScan(const ScanCommandOptions& opt, Provenance provenance) {
  using namespace vision;
  if (opt.set.empty() == opt.batch.empty())
    throw InputError({"", 0, "SET/--batch"}, "give either one fringe set or --batch LIST");
  if (!(opt.radius >= 0)) throw InputError({"", 0, "--radius"}, "must be >= 0 mm (0 = unknown)");
  // The heap keeps freed image-sized blocks instead of returning them to the kernel (main.cpp,
  // huge_pages.h): the scan frees and re-allocates frames and maps of the same sizes (left then
  // right camera, stage after stage, set after set), and fresh pages cost a page fault each (a
  // third fewer faults and ~15 % less CPU on the SLMaster set, docs/performance.md).
  ScanOptions options;
  options.calibration_path = opt.calib;
  options.sphere.radius_mm = opt.radius;
  options.sphere.fix_radius = opt.fix_radius;
  options.sphere.max_spheres = opt.spheres;
  options.match.min_depth_mm = opt.min_depth;
  options.match.max_depth_mm = opt.max_depth;
  options.decode.correct_nonlinearity = !opt.no_nonlinearity;
  options.decode.coordinate_filter.radius_px = opt.phase_filter;
  options.match.lr_sigma_factor = opt.lr_sigma_factor;
  options.match.kernel_estimate = opt.kernel_estimate == "off" ? vision::StereoMatchOptions::KernelEstimate::kOff
                                                               : vision::StereoMatchOptions::KernelEstimate::kAuto;
  options.match.noise_bias_term = !opt.no_noise_term;
  options.decode.noise_from_neighbours = !opt.whole_residual_sigma;
  options.decode.modulation_rule =
      opt.modulation_rule == "fixed" ? vision::ModulationRule::kFixed : vision::ModulationRule::kSigma;
  options.decode.max_order_error_probability = opt.max_order_error;
  options.projector_ray_plane = opt.ray_plane;
  options.roi = ParseScanRoi(opt.roi);
  options.roi.margin_mm = opt.roi_margin;
  options.roi.coarse_stride = opt.roi_stride;
  options.read_rows_on_demand = !opt.load_whole_frames;
  options.tri_view = opt.tri_view;
  options.projector_calibration_path = opt.projector_calib;
  ThrowIfInvalid(options.Validate(), "ScanOptions");

  // The outputs may not be or contain any input (the manifests, their images, the calibration).
  std::vector<std::string> inputs = {opt.batch, opt.calib, opt.truth, opt.projector_calib};
  auto add_set = [&inputs](const std::string& manifest) {
    for (const std::string& f : ReadFringeManifest(manifest).InputFiles()) inputs.push_back(f);
  };
  if (!opt.batch.empty()) {
    const std::vector<std::string> sets = ReadScanBatchList(opt.batch);
    for (const std::string& set : sets) {
      try {
        add_set(set);
      } catch (const InputError&) {
        inputs.push_back(set);  // unreadable: the batch reports it on its row; still never overwritten
      }
    }
    CheckOutputAgainstInputs(opt.out, inputs, "--out");
    // The batch's own provenance names the list and the calibration; each set's folder adds its files.
    for (const std::string& f : {opt.batch, opt.calib, opt.truth, opt.projector_calib})
      AddProvenanceFile(&provenance, f);
    ProgressCallback progress;
    if (!opt.quiet) progress = ProgressPrinter("sets");
    // A shard scans every N-th set into the same folders a single run would, and writes its rows
    // to results.shard-K-of-N.csv; `ramtk merge` joins the shards (docs/cluster.md).
    std::vector<std::size_t> positions(sets.size());
    for (std::size_t i = 0; i < sets.size(); ++i) positions[i] = i;
    std::string results_name = "results.csv";
    if (!opt.shard.empty()) {
      const ScanShard shard = ParseScanShard(opt.shard);
      positions = ShardPositions(sets.size(), shard);
      results_name = ShardResultsName(shard);
    }
    const std::string results = opt.out + "/" + results_name;
    std::filesystem::create_directories(opt.out);
    // One run at a time per results file: a second run into this --out (or this shard) fails here.
    const OutputLock lock(results, "--out");
    if (!opt.force && !opt.resume) RefuseToReplaceEarlierResults(results, sets, positions, opt.out);
    ScanBatchReuse reuse;
    reuse.overwrite = opt.force;
    reuse.resume = opt.resume;
    reuse.settings = ResultSettings(opt).ToString();
    reuse.provenance = [&provenance](const std::string&, const std::string&) { return provenance; };
    const auto started = std::chrono::steady_clock::now();
    const std::vector<ScanBatchRow> rows =
        RunScanBatch(ReadScanBatchEntries(opt.batch), options, opt.out, opt.jobs, reuse, progress, positions);
    const ScanBatchSummary totals =
        SummariseScanBatch(rows, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    const std::string csv = ScanBatchCsv(rows);
    WriteFileAtomically(results, csv);
    WriteProvenanceSidecar(results, provenance);  // results.provenance.json
    if (!opt.quiet) std::cout << csv;  // a campaign's 1800 rows are in results.csv
    if (opt.report) {
      const std::string page = results_name.substr(0, results_name.size() - 4) == "results"
                                   ? std::string("report.html")
                                   : "report" + results_name.substr(7, results_name.size() - 11) + ".html";
      report::HtmlReport html = ScanBatchReport(rows, opt.out);
      html.AddProvenance(provenance);
      html.Write(opt.out + "/" + page);
      std::cout << "wrote " << opt.out << "/" << page << "\n";
    }
    std::cout << totals.BriefReport() << "; wrote " << opt.out << "/" << results_name << "\n";
    return totals.errors ? kExitBadInput : totals.no_sphere ? kExitNoSolution : kExitOk;
  }

  add_set(opt.set);
  CheckOutputAgainstInputs(opt.out, inputs, "--out");
  for (const std::string& f : inputs) AddProvenanceFile(&provenance, f);
  const std::vector<Sphere> truth = opt.truth.empty() ? std::vector<Sphere>{} : ReadTruthSpheres(opt.truth);
  // cloud.ply and depth.png are written beside the sphere fit; the folder is checked before the scan.
  ScanOutputWriter writer(opt.out, opt.force, opt.set);
  writer.SetProvenance(provenance);
  options.on_cloud = writer.OnCloud();
  const ScanResult result = ScanFringeSet(opt.set, options);
  writer.Finish(result, opt.report);
  std::cout << result.summary.BriefReport() << "\n";
  if (result.summary.mode == "stereo" && result.summary.match.kernel.status != "off")
    std::cout << SamplingKernelLine(result.summary.match.kernel) << "\n";
  if (options.roi.mode != ScanRoiOptions::Mode::kFull)
    std::cout << "roi " << result.summary.roi_source << ": left " << WindowText(result.summary.windows.left)
              << ", right " << WindowText(result.summary.windows.right) << " (x,y,w,h px)\n";
  if (std::isfinite(result.summary.calibration_rms_px))
    std::cout << "calibration: session RMS " << result.summary.calibration_rms_px << " px, "
              << result.summary.calibration_parameter_std.size() << " parameter sigmas (in summary.json)\n";
  if (!truth.empty()) {
    const std::vector<int> match = MatchTruthSpheres(result.summary.spheres, truth);
    for (std::size_t i = 0; i < match.size(); ++i) {
      if (match[i] < 0) continue;
      const SphereResult& r = result.summary.spheres.spheres[i];
      const Sphere& t = truth[static_cast<std::size_t>(match[i])];
      const Vec3 e = r.centre_mm - t.centre_in_left;
      std::printf(
          "error vs truth (%s): centre (%+.4f, %+.4f, %+.4f) mm, |e| %.1f um (predicted sigma %.1f um, CRLB %.1f "
          "um); radius %+.1f um\n",
          t.name.c_str(), e.x(), e.y(), e.z(), 1000 * e.norm(), 1000 * r.CentreSigma().norm(),
          1000 * r.crlb_centre_sigma_mm.norm(), 1000 * (r.radius_mm - t.radius));
    }
  }
  std::cout << "wrote " << opt.out << " (" << vision::ScanOutputFileList(opt.report) << ")\n";
  return result.summary.spheres.spheres.empty() ? kExitNoSolution : kExitOk;
}

}  // namespace

void RegisterScanCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<ScanCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "scan", "Stereo fringe set -> point cloud (PLY) and sphere centres (JSON) in the left-camera frame");
  sub->add_option("set", opt->set, "Fringe image set manifest (JSON)");
  CLI::Option* batch =
      sub->add_option("--batch", opt->batch,
                      "File listing one manifest per line, optionally followed by a predicted ball centre X,Y,Z (mm, "
                      "left camera: that set is scanned in windows around it); scanned in parallel, one CSV row each");
  sub->add_option("--calib", opt->calib, "Stereo calibration (default: the manifest's)");
  sub->add_option("--out", opt->out, "Output folder (batch: one sub-folder per set)")->capture_default_str();
  sub->add_option("--radius", opt->radius, "Sphere radius prior, mm (0 = unknown)")->capture_default_str();
  sub->add_flag("--fix-radius", opt->fix_radius, "Hold the radius at --radius; fit the centre only");
  sub->add_option("--spheres", opt->spheres, "Spheres to look for (2 for a ball bar)")->capture_default_str();
  sub->add_option("--min-depth", opt->min_depth, "Nearest depth searched, mm")->capture_default_str();
  sub->add_option("--max-depth", opt->max_depth, "Farthest depth searched, mm")->capture_default_str();
  sub->add_option("--truth", opt->truth, "Simulator truth.json: print the centre and radius errors");
  sub->add_option("--jobs", opt->jobs,
                  "Sets scanned at once with --batch, and the threads the batch runs on (a set in flight alone "
                  "uses them all)")
      ->capture_default_str();
  CLI::Option* force =
      sub->add_flag("--force", opt->force, "Replace existing outputs (with --batch: scan every set again)");
  sub->add_flag("--resume", opt->resume,
                "With --batch: keep every set an earlier run into --out finished with the same options (its row.csv) "
                "and scan the rest")
      ->excludes(force)
      ->needs(batch);
  sub->add_flag("-q,--quiet", opt->quiet,
                "No progress bar; with --batch, no per-set table on stdout (results.csv has it)");
  sub->add_flag("--no-nonlinearity", opt->no_nonlinearity, "Do not correct the projector nonlinearity (as decode)");
  sub->add_option("--phase-filter", opt->phase_filter,
                  "Smooth each decoded coordinate map with a quadratic fit over a (2R+1)^2 window, R px (0 = off, "
                  "at most 6); the smoothing is carried into every point's sigma")
      ->check(CLI::Range(0, 6));
  sub->add_flag("--whole-residual-sigma", opt->whole_residual_sigma,
                "sigma_I = the whole sinusoid-fit residual (harmonics included, no ripple term)");
  sub->add_option("--lr-sigma-factor", opt->lr_sigma_factor,
                  "Left-right check also passes within this many back-match sigmas (0: fixed 0.5 px only)")
      ->capture_default_str();
  sub->add_option("--kernel-estimate", opt->kernel_estimate,
                  "A camera whose calibration states no sampling_kernel: auto (estimate the kernel's variance from "
                  "the matched pixels' modulation and apply the matcher's kernel terms with it, docs/scan.md; "
                  "costs ~40 % more time on a 1280x1024 pair) or off (no kernel terms unless both cameras state one)")
      ->check(CLI::IsMember({"auto", "off"}))
      ->capture_default_str();
  sub->add_flag("--no-noise-term", opt->no_noise_term,
                "Match without the noise's second-order term (the mean offset of a noisy root on a curved "
                "coordinate map, docs/scan.md)");
  sub->add_flag("--ray-plane", opt->ray_plane,
                "Camera–projector set with both fringe directions (cross_cameras): triangulate ray–plane from the "
                "manifest's direction alone, not ray–ray");
  sub->add_option("--modulation-rule", opt->modulation_rule,
                  "Weak-fringe pixels: sigma (rejected from their own phase noise: the order-error probability "
                  "and the noise floor) or fixed (modulation below 2% of full scale, brightest sample below 2%)")
      ->check(CLI::IsMember({"sigma", "fixed"}))
      ->capture_default_str();
  sub->add_option("--max-order-error", opt->max_order_error,
                  "Sigma rule: the largest accepted probability of a wrong period order at a pixel")
      ->check(CLI::Range(1e-12, 0.5))
      ->capture_default_str();
  const vision::ScanOutputFormat& report_row = vision::ScanOutputFormatNamed("report");
  sub->add_flag("--report", opt->report,
                "Also write " + report_row.file + ": " + report_row.help + ". With --batch: one page for the batch");
  sub->add_option("--roi", opt->roi,
                  "Decode and match only windows around the ball: full (every pixel), auto (a coarse pass over "
                  "every few pixels finds the ball first; the full frame if it finds none), or X,Y,Z = a predicted "
                  "ball_in_left_camera in mm (e.g. from the robot pose). The cloud then holds the windows' points "
                  "only (docs/scan.md)")
      ->capture_default_str();
  sub->add_option("--roi-margin", opt->roi_margin,
                  "mm added to the ball radius before its silhouette bounds the window: at least the error of a "
                  "predicted centre")
      ->capture_default_str();
  sub->add_option("--roi-stride", opt->roi_stride,
                  "--roi auto: the coarse pass keeps every N-th pixel in x and y (0: automatic, the coarse left "
                  "image at most 350 px wide)")
      ->capture_default_str();
  sub->add_flag("--load-whole-frames", opt->load_whole_frames,
                "With --roi: load every frame whole even when its rows can be read alone (uncompressed 8-bit grey "
                "BMP; by default only the rows the coarse pass and the windows read are read): for comparisons");
  CLI::Option* tri_view = sub->add_flag(
      "--tri-view", opt->tri_view,
      "Stereo set: triangulate the left pixels without a stereo point against the projector (its calibration: "
      "--projector-calib or the manifest's projector_calibration), each with its sigma; whole frame only");
  sub->add_option("--projector-calib", opt->projector_calib,
                  "With --tri-view: the left camera and projector's calibration (default: the manifest's)")
      ->needs(tri_view);
  sub->add_option("--shard", opt->shard,
                  "With --batch: scan only shard K of N (every N-th set from the K-th) into results.shard-K-of-N.csv; "
                  "join the shards with `ramtk merge` (docs/cluster.md)")
      ->needs(batch);
  sub->callback([opt, exit_code, sub]() {
    opt->hooks = ApplyTestHooksFromEnvironment();
    *exit_code = RunScan(*opt, CommandProvenance(sub));
  });
}

}  // namespace ramtk::tools
