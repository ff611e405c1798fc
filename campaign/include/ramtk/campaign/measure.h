#pragma once
// `ramtk measure`: joins the ball centres of a scan batch (one fringe set per robot pose per
// cycle) with the robot controller's log into the robot-measurement CSV of docs/formats.md
// (`cycle,time_s,pose,q1..q6,x,y,z`), with the centre covariance as extra columns
// cov_xx..cov_yz (mm², kinematics::kCentreCovarianceColumns) and the log's extra columns (joint
// temperatures) carried through.
//
// Captures are matched to log rows by set id when the log has a `set` column, otherwise by the
// nearest capture time (the manifest's `capture_time_s`) within a tolerance. A set without a
// sphere (or whose scan failed) is reported in the summary and left out, never written as a zero.

#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/measurements_io.h"
#include "ramtk/vision/scan/scan_batch.h"

namespace ramtk::campaign {

// One scanned capture: where it came from and the centre found in it.
struct CaptureCentre {
  std::string set;          // manifest path (as listed in the batch, normalised)
  std::string id;           // the manifest's folder name (the id a log's `set` column names)
  int line = 0;             // 1-based line in results.csv (0 when not read from a file)
  bool has_time = false;    // the manifest gave capture_time_s
  double time_s = 0.0;      // capture time, the controller log's clock (s)
  std::string status;       // "ok", "no sphere found", "error" (as the scan batch wrote it)
  std::string message;      // the scan's reason when there is no centre
  bool has_sphere = false;
  Vec3 centre_mm = Vec3::Zero();        // ball_in_sensor (the left camera frame), mm
  Mat3 covariance_mm2 = Mat3::Zero();  // of centre_mm
};

// Centres of an in-memory batch (RunScanBatch); times from each manifest's capture_time_s.
std::vector<CaptureCentre> CentresFromScanBatch(const std::vector<vision::ScanBatchRow>& rows);

// Centres from a batch's results.csv (`ramtk scan --batch` output; relative `set` and `out_dir`
// paths are taken against results.csv's folder, or as written when only that exists): the full
// covariance is read from each set's spheres.json in its out_dir (the CSV's sigma columns when that file is
// missing, as a diagonal covariance — logged as a warning). InputError names results.csv, the line
// and the field of anything malformed.
std::vector<CaptureCentre> ReadScanResults(const std::string& results_csv);

// The capture time of a fringe set: the manifest's top-level "capture_time_s" (s), which the
// decoder ignores. false when absent; InputError naming the manifest when it is not a number.
bool ReadCaptureTime(const std::string& manifest_path, double* time_s);

struct MeasureOptions {
  // Matching by time (used when the log has no `set` column, or always with by_time): a capture
  // takes the log row nearest in time; farther than this (s) is an error.
  double time_tolerance_s = 0.5;
  bool by_time = false;  // match by time even when the log has a `set` column
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

struct LeftOut {
  std::string set;     // manifest path
  int cycle = -1;      // from the matched log row (-1 when unmatched)
  int pose = -1;
  std::string reason;  // "no sphere found: ...", "error: ...", "no log row within 0.5 s", ...
};

struct MeasureSummary {
  std::string match = "id";  // "id" or "time"
  int captures = 0;          // captures given
  int written = 0;           // rows written
  std::vector<LeftOut> left_out;     // captures without a centre (reported, not written)
  int unused_log_rows = 0;           // log rows no capture matched
  double worst_time_offset_s = 0.0;  // largest |capture time − log time| of a matched pair (time matching)
  std::vector<std::string> warnings;
  std::string BriefReport() const;  // one line
};

struct ControllerLog;  // controller_log.h

// The join. InputError (naming the log's or results' file, line and field) when a capture with a
// centre matches no log row, two captures match one log row, a set id repeats, or (time
// matching) a capture has no time.
kinematics::RobotMeasurementSet JoinCentresWithLog(const std::vector<CaptureCentre>& captures, const ControllerLog& log,
                                                   const MeasureOptions& options, MeasureSummary* summary = nullptr);

// Drift is measured pose by pose against the cold cycle, so a pose must have a centre in every
// cycle. The poses of `measured` missing from some cycle that has rows, and the poses of
// `expected` (e.g. the planned poses) absent from `measured` altogether, ascending.
std::vector<int> PosesMissingInSomeCycle(const kinematics::RobotMeasurementSet& measured,
                                         const kinematics::RobotMeasurementSet& expected);
// `set` without the rows of the given poses (the other fields unchanged).
kinematics::RobotMeasurementSet DropPoses(const kinematics::RobotMeasurementSet& set, const std::vector<int>& poses);

}  // namespace ramtk::campaign
