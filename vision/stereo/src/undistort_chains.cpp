// Rows of the stereo match's undistortions side by side (undistort_chains.h).
#include "ramtk/vision/stereo/detail/undistort_chains.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/distort_lanes.h"

namespace ramtk::vision::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The seed of the pixel at column x after the row's solutions `prev` (at column xp) and `prev2`
// (at xp2), as RunPass took it.
Vec2 Seed(int x, int xp, int xp2, const Vec2& prev, const Vec2& prev2, const Vec2& distorted) {
  return xp == x - 1 && xp2 == x - 2 ? Vec2(2.0 * prev - prev2) : std::isfinite(prev.x()) ? prev : distorted;
}

Vec2 Distorted(const CameraIntrinsics& camera, int x, int y) {
  return Vec2((x - camera.cx) / camera.fx, (y - camera.cy) / camera.fy);
}

// The rays of entry k of a chain from its ideal point, by Eigen as the walk took them.
void ScalarRays(const ChainRays& rays, const UndistortChain& chain, int k) {
  const Vec3 ray(chain.ideal_x[k], chain.ideal_y[k], 1.0);
  const Vec3 a = rays.rotation * ray;
  chain.a_x[k] = a.x(), chain.a_y[k] = a.y(), chain.a_z[k] = a.z();
  if (!rays.rectified) return;
  const Vec3 r = rays.rect_from_camera * ray;
  chain.rs_z[k] = r.z();
  chain.rs_u[k] = rays.rect_f * r.x() / r.z();
  chain.rs_v[k] = rays.rect_f * r.y() / r.z();
}

void ScalarChain(const CameraIntrinsics& camera, const UndistortChain& chain, const ChainRays* rays) {
  Vec2 prev(kNaN, kNaN), prev2(kNaN, kNaN);
  int xp = -10, xp2 = -10;
  for (int k = 0; k < chain.count; ++k) {
    const int x = chain.xs[k];
    const Vec2 distorted = Distorted(camera, x, chain.y);
    const Vec2 ideal = UndistortNormalized(camera.distortion, distorted, Seed(x, xp, xp2, prev, prev2, distorted));
    chain.ideal_x[k] = ideal.x();
    chain.ideal_y[k] = ideal.y();
    if (rays) ScalarRays(*rays, chain, k);
    prev2 = prev;
    xp2 = xp;
    prev = ideal;
    xp = x;
  }
}

RAMTK_AVX2_INLINE __m256d K(double v) { return _mm256_set1_pd(v); }
RAMTK_AVX2_INLINE __m256d Add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }

// Four chains on four lanes. Each lane takes UndistortNormalized's operations in its order:
// DistortNormalized's and DistortNormalizedJacobian's expressions as written (camera_model.h),
// the infinity-norm test, the 2 x 2 solve. A lane whose residual is ever not finite (only a
// diverging lens model) is redone by the scalar function, whose handling of NaN it then keeps.
// M (x, y, 1) on four lanes, summed as Eigen's fixed-size product sums it (checked against it in
// tests/vision/undistort_chains_test.cpp): rows 0 and 1 as (M(i,0) x + M(i,1) y) + M(i,2), the
// third as M(2,0) x + (M(2,1) y + M(2,2)).
RAMTK_AVX2_INLINE void Turn(const Mat3& m, __m256d x, __m256d y, __m256d* out) {
  for (int i = 0; i < 2; ++i) out[i] = Add(Add(Mul(K(m(i, 0)), x), Mul(K(m(i, 1)), y)), Mul(K(m(i, 2)), K(1.0)));
  out[2] = Add(Mul(K(m(2, 0)), x), Add(Mul(K(m(2, 1)), y), Mul(K(m(2, 2)), K(1.0))));
}

RAMTK_AVX2 void FourChains(const CameraIntrinsics& camera, const UndistortChain* chains, const ChainRays* rays) {
  const Distortion& d = camera.distortion;
  const __m256d two = K(2.0);
  const __m256d sign = _mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull)));
  const __m256d tolerance = K(1e-15);
  int steps = 0;
  for (int i = 0; i < 4; ++i) steps = std::max(steps, chains[i].count);
  // Lane state: the last two solutions and their columns (-10: none); each lane's row.
  __m256d px = K(kNaN), py = K(kNaN), p2x = K(kNaN), p2y = K(kNaN);
  __m128i xp = _mm_set1_epi32(-10), xp2 = _mm_set1_epi32(-10);
  const __m128i counts = _mm_setr_epi32(chains[0].count, chains[1].count, chains[2].count, chains[3].count);
  const __m256d row_dy = _mm256_setr_pd((chains[0].y - camera.cy) / camera.fy, (chains[1].y - camera.cy) / camera.fy,
                                        (chains[2].y - camera.cy) / camera.fy, (chains[3].y - camera.cy) / camera.fy);
  const __m256d cx = K(camera.cx), fx = K(camera.fx);
  for (int k = 0; k < steps; ++k) {
    // Each lane's pixel, distorted point ((x - cx) / fx, (y - cy) / fy) and seed, as Seed picks
    // it (idle lanes: the origin, solved at once).
    alignas(16) int col[4];
    for (int i = 0; i < 4; ++i) col[i] = k < chains[i].count ? chains[i].xs[k] : 0;
    const __m128i xv = _mm_load_si128(reinterpret_cast<const __m128i*>(col));
    const __m128i active32 = _mm_cmpgt_epi32(counts, _mm_set1_epi32(k));
    const __m256d active = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(active32));
    const __m256d vdx = _mm256_and_pd(active, _mm256_div_pd(Sub(_mm256_cvtepi32_pd(xv), cx), fx));
    const __m256d vdy = _mm256_and_pd(active, row_dy);
    const __m128i lin32 = _mm_and_si128(_mm_cmpeq_epi32(xp, _mm_sub_epi32(xv, _mm_set1_epi32(1))),
                                        _mm_cmpeq_epi32(xp2, _mm_sub_epi32(xv, _mm_set1_epi32(2))));
    const __m256d lin = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(lin32));
    const __m256d finite = _mm256_cmp_pd(Sub(px, px), _mm256_setzero_pd(), _CMP_EQ_OQ);
    const __m256d sx =
        _mm256_and_pd(active, _mm256_blendv_pd(_mm256_blendv_pd(vdx, px, finite), Sub(Mul(two, px), p2x), lin));
    const __m256d sy =
        _mm256_and_pd(active, _mm256_blendv_pd(_mm256_blendv_pd(vdy, py, finite), Sub(Mul(two, py), p2y), lin));
    __m256d x = sx, y = sy;
    __m256d done = _mm256_setzero_pd(), bad = _mm256_setzero_pd();
    for (int iter = 0; iter < 30; ++iter) {
      __m256d r2, radial, ux, uy;
      DistortNormalized4(d, x, y, &r2, &radial, &ux, &uy);
      const __m256d rx = Sub(ux, vdx), ry = Sub(uy, vdy);
      const __m256d ax = _mm256_andnot_pd(sign, rx), ay = _mm256_andnot_pd(sign, ry);
      // Any non-finite residual: the scalar function redoes the lane.
      bad = _mm256_or_pd(bad, _mm256_cmp_pd(Add(Mul(rx, K(0.0)), Mul(ry, K(0.0))), K(0.0), _CMP_NEQ_UQ));
      const __m256d converged = _mm256_cmp_pd(_mm256_max_pd(ax, ay), tolerance, _CMP_LT_OQ);
      done = _mm256_or_pd(done, converged);
      if (_mm256_movemask_pd(done) == 0xF) break;
      __m256d j00, j01, j10, j11;
      DistortJacobian4(d, x, y, r2, radial, &j00, &j01, &j10, &j11);
      const __m256d det = Sub(Mul(j00, j11), Mul(j01, j10));
      const __m256d nx = Sub(x, _mm256_div_pd(Sub(Mul(j11, rx), Mul(j01, ry)), det));
      const __m256d ny = Sub(y, _mm256_div_pd(Sub(Mul(j00, ry), Mul(j10, rx)), det));
      x = _mm256_blendv_pd(nx, x, done);
      y = _mm256_blendv_pd(ny, y, done);
    }
    alignas(32) double ox[4], oy[4];
    _mm256_store_pd(ox, x);
    _mm256_store_pd(oy, y);
    if (const int redo = _mm256_movemask_pd(_mm256_and_pd(bad, active))) {
      alignas(32) double dx[4], dy[4], seed_x[4], seed_y[4];
      _mm256_store_pd(dx, vdx), _mm256_store_pd(dy, vdy), _mm256_store_pd(seed_x, sx), _mm256_store_pd(seed_y, sy);
      for (int i = 0; i < 4; ++i) {
        if (!(redo >> i & 1)) continue;
        const Vec2 ideal = UndistortNormalized(d, Vec2(dx[i], dy[i]), Vec2(seed_x[i], seed_y[i]));
        ox[i] = ideal.x(), oy[i] = ideal.y();
      }
      x = _mm256_load_pd(ox), y = _mm256_load_pd(oy);
    }
    for (int i = 0; i < 4; ++i) {
      if (k >= chains[i].count) continue;
      chains[i].ideal_x[k] = ox[i];
      chains[i].ideal_y[k] = oy[i];
    }
    p2x = _mm256_blendv_pd(p2x, px, active), p2y = _mm256_blendv_pd(p2y, py, active);
    px = _mm256_blendv_pd(px, x, active), py = _mm256_blendv_pd(py, y, active);
    xp2 = _mm_blendv_epi8(xp2, xp, active32);
    xp = _mm_blendv_epi8(xp, xv, active32);
    if (!rays) continue;
    // The rays of the four solutions (idle lanes: the origin's, not stored).
    const __m256d ix = _mm256_load_pd(ox), iy = _mm256_load_pd(oy);
    __m256d a[3];
    Turn(rays->rotation, ix, iy, a);
    alignas(32) double out[6][4];
    for (int j = 0; j < 3; ++j) _mm256_store_pd(out[j], a[j]);
    if (rays->rectified) {
      __m256d r[3];
      Turn(rays->rect_from_camera, ix, iy, r);
      const __m256d f = K(rays->rect_f);
      _mm256_store_pd(out[3], _mm256_div_pd(Mul(f, r[0]), r[2]));
      _mm256_store_pd(out[4], _mm256_div_pd(Mul(f, r[1]), r[2]));
      _mm256_store_pd(out[5], r[2]);
    }
    for (int i = 0; i < 4; ++i) {
      if (k >= chains[i].count) continue;
      chains[i].a_x[k] = out[0][i], chains[i].a_y[k] = out[1][i], chains[i].a_z[k] = out[2][i];
      if (rays->rectified) chains[i].rs_u[k] = out[3][i], chains[i].rs_v[k] = out[4][i], chains[i].rs_z[k] = out[5][i];
    }
  }
}

}  // namespace

void UndistortChains(const CameraIntrinsics& camera, const UndistortChain* chains, int n, const ChainRays* rays) {
  int i = 0;
  // The lanes evaluate the 5-coefficient model; the other lens models take the scalar chain.
  if (Avx2Kernels() && !camera.distortion.IsZero() && camera.distortion.model == camera::LensModel::kPinhole5)
    for (; i + 4 <= n; i += 4) FourChains(camera, chains + i, rays);
  for (; i < n; ++i) ScalarChain(camera, chains[i], rays);
}

}  // namespace ramtk::vision::detail
