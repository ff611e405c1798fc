#pragma once
// Optional smoothing of a decoded projector-coordinate map in the phase domain, with its effect
// carried into each pixel's sigma: dense matches on low-modulation captures.
//
// Each valid pixel's coordinate is replaced by the value at its centre of a least-squares
// quadratic surface c0 + c1 x + c2 y + c3 x² + c4 xy + c5 y² fitted to the valid pixels of its
// (2R+1)² window: a 2-D Savitzky–Golay filter. A quadratic is exact for the surface's own shape up
// to second order, so curved surfaces are not flattened (a plain average would bias a ball's
// apex by the curvature). The result is linear in the inputs, c_f = Σ k_i c_i, so its sigma is
//   σ_f² = Σ k_i² σ_random,i² + ripple²
// with σ_random² = σ² − ripple²: the pixel-independent noise averages down, the projector
// ripple (DecodeSummary::phase_ripple_rad, the same at neighbouring pixels) does not. Neighbouring
// filtered pixels share noise; the scan's sphere fit widens its neighbour-correlation estimate to
// the filter's reach (2R) so its covariance accounts for that.
//
// The ripple is kept whole in σ_f: that is exact for a ripple smooth at the window's scale and
// an upper bound otherwise (a pixel-scale ripple, e.g. the aliased harmonics of a 12-step set, is
// partly averaged out; on the real SLMaster set σ_f is then conservative, docs/scan.md).
//
// A pixel keeps its own value (and sigma) when fewer than min_valid_fraction of its window are
// valid, or when the filtered value departs from its own by more than max_departure_sigma times
// sqrt(var(random part of the difference) + ripple²) (a depth edge or a surface the quadratic
// does not follow inside the window).
#include <opencv2/core.hpp>
#include <string>

namespace ramtk::vision {

struct DecodedCamera;

struct CoordinateFilterOptions {
  int radius_px = 0;                 // window half-width R (px); 0 = no filtering, at most 6
  double min_valid_fraction = 0.6;   // of the window's pixels, the centre always included
  double max_departure_sigma = 4.0;  // |filtered − own| limit, in σ of that difference
  // Returns "" or what is wrong.
  std::string Validate() const;
};

struct CoordinateFilterSummary {
  int radius_px = 0;
  long filtered = 0;              // pixels given their filtered value
  long kept_sparse = 0;           // kept their own value: too few valid pixels in the window
  long kept_departure = 0;        // kept their own value: the filtered value departed too far
  double median_sigma_ratio = 1;  // median of σ_after / σ_before over the filtered pixels
};

// Filters decoded->coordinate and decoded->sigma_coordinate in place (and sigma_phase when it is
// kept); `ripple_px` is the ripple part of sigma_coordinate (projector px). InputError for bad
// options.
CoordinateFilterSummary FilterCoordinate(const CoordinateFilterOptions& options, double ripple_px,
                                         DecodedCamera* decoded);

}  // namespace ramtk::vision
