// The AVX2 switch (avx2.h).
#include "ramtk/vision/kernels/avx2.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace ramtk::vision::detail {
namespace {

// -1: not decided yet; 0 or 1 after the first call or SetAvx2Kernels.
std::atomic<int> g_avx2{-1};

// The CPU's AVX2 (libgcc checks that the OS saves the YMM registers too), unless RAMTK_AVX2=0.
bool CpuHasAvx2() {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2")) return false;
  const char* env = std::getenv("RAMTK_AVX2");
  return !(env && std::strcmp(env, "0") == 0);
}

}  // namespace

bool Avx2Kernels() {
  int v = g_avx2.load(std::memory_order_relaxed);
  if (v < 0) {
    v = CpuHasAvx2() ? 1 : 0;
    g_avx2.store(v, std::memory_order_relaxed);
  }
  return v == 1;
}

void SetAvx2Kernels(bool on) { g_avx2.store(on && CpuHasAvx2() ? 1 : 0, std::memory_order_relaxed); }

}  // namespace ramtk::vision::detail
