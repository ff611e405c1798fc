// The fringe diagnosis and the camera's sampling kernel, on sets written from the physics alone
// (kernel_physics_generator.h): clean point-sampled and area-sampled sets are `none` when the
// diagnosis is told their kernel, and a set rendered with another kernel than the stated one is
// named `sampling_kernel` with the kernel that fits.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "kernel_physics_generator.h"
#include "ramtk/core/error.h"
#include "ramtk/diagnose/fringe/fringe.h"
#include "ramtk/diagnose/fringe/fringe_hidden.h"

namespace ramtk::diagnose {
namespace {

Diagnosis Diagnose(const test_kernel::PhysicsSet& set, double fill, double psf, unsigned seed) {
  DiagnoseOptions o;
  o.seed = seed;
  o.with = {"fill_factor=" + std::to_string(fill), "psf_sigma_px=" + std::to_string(psf)};
  return DiagnoseFringeFrames(set.manifest, set.frames, 255.0, o, "physics");
}

bool NamesOrAmbiguousWith(const Diagnosis& d, const std::string& effect) {
  if (d.cause == effect) return true;
  return d.cause == kAmbiguous && std::find(d.look_alikes.begin(), d.look_alikes.end(), effect) != d.look_alikes.end();
}

struct Kernel {
  double fill, psf;
};

// Point sampling (the renders: one ray per pixel, sharp code edges, a projector pixel of
// 0.3 camera px, so its half pixel lies beyond one camera pixel), area sampling, area + PSF.
class CleanKernel : public ::testing::TestWithParam<std::tuple<Kernel, unsigned>> {};

TEST_P(CleanKernel, IsNoneWhenTheKernelIsStated) {
  const auto [k, seed] = GetParam();
  const Diagnosis d = Diagnose(test_kernel::RenderFringes(k.fill, k.psf, 0.3, seed), k.fill, k.psf, seed);
  SCOPED_TRACE("fill " + std::to_string(k.fill) + " psf " + std::to_string(k.psf) + ": " + d.cause + " / " +
               d.explaining_variable);
  EXPECT_EQ(d.cause, "none");
  EXPECT_LT(d.residual_rms, 1.1 * d.noise_floor_rms);
}

INSTANTIATE_TEST_SUITE_P(PointAndArea, CleanKernel,
                         ::testing::Combine(::testing::Values(Kernel{0, 0}, Kernel{1, 0}), ::testing::Values(21u, 22u, 23u)));
INSTANTIATE_TEST_SUITE_P(AreaAndPsf, CleanKernel, ::testing::Values(std::make_tuple(Kernel{1, 0.5}, 24u)));

// A camera pixel spanning 1.5 projector px, rendered with a PSF of 0.8 px while point sampling is
// stated: the wrong kernel is named (alone, or as the look-alike of a camera blur, the same physics)
// with the PSF that fits; stated right, the same data are `none`.
TEST(FringeKernel, AWrongKernelIsNamedWithTheKernelThatFits) {
  const test_kernel::PhysicsSet set = test_kernel::RenderFringes(0, 0.8, 1.5, 31);
  const Diagnosis wrong = Diagnose(set, 0, 0, 31);
  SCOPED_TRACE(wrong.cause);
  EXPECT_TRUE(NamesOrAmbiguousWith(wrong, "sampling_kernel"));
  EXPECT_GE(wrong.excess_removed, 0.5);
  const CandidateFit* kernel = nullptr;
  for (const CandidateFit& c : wrong.candidates)
    if (c.effect == "sampling_kernel") kernel = &c;
  ASSERT_NE(kernel, nullptr);
  EXPECT_NEAR(kernel->parameters.at("psf_sigma_px"), 0.8, 0.1);
  EXPECT_LE(kernel->parameters.at("fill_factor"), 0.25);
  EXPECT_GT(kernel->sigmas.at("psf_sigma_px"), 0.0);
  const Diagnosis right = Diagnose(set, 0, 0.8, 31);
  EXPECT_EQ(right.cause, "none") << right.cause;
}

// The vision simulator's point-sampled render (one ray per pixel) blurred by a camera PSF of 0.8 px
// (its Gaussian blur of the image), point sampling stated: the kernel that fits has that PSF.
TEST(FringeKernel, TheSimulatorsPsfIsRecovered) {
  HiddenFringeDraw draw;
  draw.seed = 41;
  draw.supersampling = 1;
  draw.psf_sigma_px = 0.8;
  const HiddenFringeSet set = SimulateHiddenFringe(draw);
  DiagnoseOptions o;
  o.seed = draw.seed;
  o.with = {"fill_factor=0"};
  const Diagnosis d = DiagnoseFringeFrames(set.manifest, set.frames, set.full_scale, o, "sim");
  SCOPED_TRACE(d.cause);
  EXPECT_TRUE(NamesOrAmbiguousWith(d, "sampling_kernel"));
  for (const CandidateFit& c : d.candidates)
    if (c.effect == "sampling_kernel") {
      EXPECT_NEAR(c.parameters.at("psf_sigma_px"), 0.8, 0.12);
      EXPECT_LE(c.parameters.at("fill_factor"), 0.25);
    }
}

TEST(FringeKernel, RejectsAKernelOutOfRange) {
  const test_kernel::PhysicsSet set = test_kernel::RenderFringes(0, 0, 0.3, 1);
  DiagnoseOptions o;
  o.with = {"fill_factor=1.5"};
  EXPECT_THROW(DiagnoseFringeFrames(set.manifest, set.frames, 255.0, o, "x"), InputError);
  o.with = {"psf_sigma_px=abc"};
  EXPECT_THROW(DiagnoseFringeFrames(set.manifest, set.frames, 255.0, o, "x"), InputError);
}

}  // namespace
}  // namespace ramtk::diagnose
