#pragma once
// The HTML report of one scan (`ramtk scan --report`): summary, stage figures, the depth picture,
// the sphere fit's residual against the view angle and a 3D view of the points around each sphere
// with the fitted surface.

#include <string>

#include "ramtk/report/html_report.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/scan/scan_batch.h"

namespace ramtk::vision {

// Figure of the radial fit residual (µm) of sphere k's inliers against the angle between the
// surface normal and the line of sight (0° = facing the left camera), with a binned mean and
// the ±median point σ band. Subsampled to at most max_points dots.
report::Figure SphereResidualFigure(const ScanResult& result, int k, size_t max_points = 6000);

// The report page. `depth_png` (optional, "" = none) is inlined.
report::HtmlReport ScanReport(const ScanResult& result, const std::string& depth_png);

// The page of a batch (`ramtk scan --batch LIST --report`): the results table with a link to each
// set's folder, and per set the centre σ, the fit RMS, the point count and the wall time.
// `out_dir` is the batch folder (links are made relative to it).
report::HtmlReport ScanBatchReport(const std::vector<ScanBatchRow>& rows, const std::string& out_dir);

}  // namespace ramtk::vision
