// Independent fringe-image generator (issue 15): a camera and a projector looking at a tilted
// plane with a smooth bump, rendered ray by ray, with photon shot noise, read noise and
// quantisation; one optical or electronic effect switched on. See README.md for the physics.
#pragma once

#include "common.h"

#include <vector>

namespace indep {

// Camera sensor: photo-electrons → digital numbers (16-bit scale).
struct SensorModel {
  double gain_dn_per_e = 1.0;  // conversion gain G, DN per electron
  double read_noise_e = 3.0;   // read noise, electrons RMS
  double black_level_dn = 400; // offset added before quantisation
  double knee_fraction = 0;    // soft knee: 0 = linear; else the DN level (fraction of full scale) above which the response compresses
};

// One pixel's DN for an expected signal of `mean_e` electrons: Poisson photon count, Gaussian
// read noise, gain, optional soft knee, rounding and clipping to [0, 65535].
double SensePixel(const SensorModel& sensor, double mean_e, Rng& rng);

// The soft-knee response on the signal above black (DN → DN): linear below the knee K, above it
// K + (S − K)·tanh((x − K)/(S − K)) with S the signal range above black.
double SoftKnee(double signal_dn, double knee_dn, double range_dn);

// Pillbox (uniform disc, geometric defocus) blur of a float image, radius in pixels.
void PillboxBlur(std::vector<float>& image, int width, int height, double radius_px);

void GenerateFringe(const GenOptions& options);

}  // namespace indep
