#pragma once
// Many scans at once (`ramtk scan --batch LIST`): the sets run in parallel (TBB), each writes its
// own output folder, and each gives one result row (CSV).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {

struct ScanBatchRow {
  std::string set;          // manifest path as listed
  std::string out_dir;      // where its outputs were written ("" if none)
  std::string status;       // "ok", "no sphere found", or "error"
  std::string message;      // the error or the no-sphere reason
  long points = 0;          // cloud size
  bool has_sphere = false;  // the first (strongest) sphere below is valid
  SphereResult sphere;      // first sphere
  double seconds = 0;       // wall time of this set
  // A row kept from an earlier run (ScanBatchReuse::resume): its CSV cells as recorded, written
  // again as they were (set and out_dir from the fields above). Empty for a set scanned now.
  std::vector<std::string> kept_cells;
};

// The options that change a set's results, as the command line names them; ToString() is the
// text recorded in each batch set's row.csv (ScanBatchReuse::settings), so a batch resumed by
// `ramtk scan --batch --resume` or from Python keeps a set only when they are equal.
struct ScanResultSettings {
  std::string calib;  // --calib as given ("" when the manifests name their own)
  double radius = 0.0;
  bool fix_radius = false;
  int spheres = 1;
  double min_depth = 0.0, max_depth = 0.0;
  bool reference_decode = false, full_search = false, curve_back_pass = false;  // test hooks
  bool no_nonlinearity = false;
  bool whole_residual_sigma = false;
  int phase_filter = 0;
  double lr_sigma_factor = 0.0;
  std::string roi;
  double roi_margin = 0.0;
  int roi_stride = 0;
  bool tri_view = false;             // --tri-view (recorded only when on)
  std::string modulation_rule = "sigma";  // --modulation-rule (recorded only when not "sigma")
  double max_order_error = 1e-4;          // --max-order-error (recorded only when not 1e-4)
  bool ray_plane = false;                 // --ray-plane (recorded only when on)
  std::string kernel_estimate = "off";    // --kernel-estimate (recorded only when not "off")
  bool no_noise_term = false;             // --no-noise-term (recorded only when on)
  std::string projector_calib;       // --projector-calib as given
  std::string ToString() const;
};

// How a batch treats the results of earlier runs in its folder.
struct ScanBatchReuse {
  bool overwrite = false;  // rescan every set, replacing its folder (--force)
  // Keep every set whose folder holds a finished row (row.csv: status neither error nor
  // cancelled) recorded for the same set with the same `settings`; rescan the others, replacing
  // their folders (--resume).
  bool resume = false;
  // The options that change a set's results, as text; recorded in each set's row.csv.
  std::string settings;
  // What each set's folder records about how it was made (not about reuse): the provenance
  // block of its summary.json, given the set's manifest and folder as recorded
  // (see paths_relative_to); the set's input files are added with their hashes. Empty: the
  // version and commit only.
  std::function<Provenance(const std::string& set, const std::string& folder)> provenance;
  // When not empty, the paths a set's folder records (summary.json `set` and `calibration`,
  // cloud.ply's comment, the provenance inputs) are written relative to this folder when they
  // lie below it (a campaign's output folder, written in a staging folder first).
  std::string paths_relative_to;
};

// One line of a batch list: a manifest and, optionally, the ball's predicted centre.
struct ScanBatchEntry {
  std::string set;  // manifest path (relative paths resolved against the list's folder)
  // "PATH X,Y,Z": the predicted ball_in_left_camera (mm), e.g. from the robot pose; the set is
  // then scanned in windows around it (ScanRoiOptions::Mode::kPredicted, whatever the batch's
  // own roi mode).
  std::optional<Vec3> predicted_centre_in_left_mm;
};

// Reads a batch list: one manifest path per line, optionally followed by whitespace and a
// predicted centre "X,Y,Z" in mm; relative paths against the list's folder; blank lines and
// lines starting with '#' are skipped. InputError naming the list (and the line) if it is empty,
// unreadable, or a centre is not three finite numbers.
std::vector<ScanBatchEntry> ReadScanBatchEntries(const std::string& path);
// The manifests of ReadScanBatchEntries, in list order.
std::vector<std::string> ReadScanBatchList(const std::string& path);

// Scans the sets, at most `parallel_sets` at a time, writing each into out_dir/NNN_<name>/ (NNN
// = the set's position in `sets`, name = the manifest's folder name). `positions` (0-based, into
// `sets`) restricts the run to those sets (a shard); empty: all. Bad input in one set is recorded
// in its row; the others go on. `progress` is called (serialised) after each set; once it returns
// false the sets not yet started are skipped, their rows with status "cancelled".
std::vector<ScanBatchRow> RunScanBatch(const std::vector<std::string>& sets, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress = {},
                                       const std::vector<std::size_t>& positions = {});
// The same with the list's entries: a set with a predicted centre is scanned in windows around it.
std::vector<ScanBatchRow> RunScanBatch(const std::vector<ScanBatchEntry>& entries, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress = {},
                                       const std::vector<std::size_t>& positions = {});
// The same with earlier results kept or replaced as `reuse` says. Each set folder written gets a
// row.csv (its results row and `reuse.settings`) once the folder is in place, so an interrupted
// batch can be resumed.
std::vector<ScanBatchRow> RunScanBatch(const std::vector<ScanBatchEntry>& entries, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, const ScanBatchReuse& reuse,
                                       const ProgressCallback& progress = {},
                                       const std::vector<std::size_t>& positions = {});
// The folder a batch writes the set at `position` (0-based, in the whole list) into:
// out_dir/NNN_<name>, name = the manifest's folder name.
std::string ScanBatchSetFolder(const std::string& out_dir, std::size_t position, const std::string& set);
// The finished row recorded in `folder`/row.csv for `set` with `settings`; nullopt when there is
// none, it is of another set or other settings, or its status is error or cancelled.
std::optional<ScanBatchRow> ReadFinishedSetRow(const std::string& folder, const std::string& set,
                                               const std::string& settings);

// A batch run's totals: its rows by status, its rate, and the process's peak memory.
struct ScanBatchSummary {
  std::size_t sets = 0, ok = 0, no_sphere = 0, errors = 0, cancelled = 0;
  double seconds = 0;          // wall time of the run
  double sets_per_second = 0;  // sets / seconds (0 for an empty run)
  double peak_memory_mb = 0;   // peak resident memory of the process so far (getrusage), MiB
  // "scanned N sets: A ok, B without a sphere, C with errors in S s (R sets/s), peak memory M MB"
  std::string BriefReport() const;
};
// The totals of `rows`, scanned in `wall_seconds`.
ScanBatchSummary SummariseScanBatch(const std::vector<ScanBatchRow>& rows, double wall_seconds);

// Shard K of N of a batch (`ramtk scan --batch LIST --shard K/N`, docs/cluster.md): 1-based.
struct ScanShard {
  int index = 1;  // K
  int count = 1;  // N
};
// "K/N" -> ScanShard; InputError (field --shard) unless K and N are decimal integers with
// 1 <= K <= N < 10^9 (a larger N is refused, never wrapped around).
ScanShard ParseScanShard(const std::string& text);
// The positions shard K of N scans: K-1, K-1+N, K-1+2N, ... (round robin, so sets of similar size
// that are listed together spread over the shards). Deterministic; the shards cover every
// position exactly once. InputError (field --shard) when N exceeds `num_sets`: no share is empty.
std::vector<std::size_t> ShardPositions(std::size_t num_sets, const ScanShard& shard);
// The shard's results file name in the batch folder: results.shard-K-of-N.csv.
std::string ShardResultsName(const ScanShard& shard);
// The shard results of a batch folder, results.shard-K-of-N.csv for K = 1..N in that order.
// InputError if the folder cannot be listed, holds none, holds shards of two different N, or
// lacks one of them.
std::vector<std::string> FindShardResults(const std::string& folder);
// Joins shard results (ScanBatchCsv files) into the single-run results.csv text, rows in list
// order. InputError naming the file (and line) when a header differs from the first file's or
// lacks `set` or `status`, a row has another number of cells than its header, a row's status is
// `error` or `cancelled` (unless `allow_errors`), a set of the list is missing, a set appears more
// often than listed (a shard run twice) or is not in the list.
std::string MergeScanShards(const std::vector<std::string>& sets, const std::vector<std::string>& shard_files,
                            bool allow_errors = false);

// CSV text: header `set,status,points,x_mm,y_mm,z_mm,radius_mm,sigma_x_mm,sigma_y_mm,sigma_z_mm,
// rms_mm,num_points,num_outliers,seconds,out_dir,message` and one row per set. With
// `relative_to` (the folder the CSV goes into) the `set` and `out_dir` paths are written relative
// to it, so the CSV and what it names can be moved together; otherwise as in the rows.
std::string ScanBatchCsv(const std::vector<ScanBatchRow>& rows, const std::string& relative_to = "");

}  // namespace ramtk::vision
