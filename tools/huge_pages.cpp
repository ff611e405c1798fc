// Transparent huge pages for the image-heavy commands (huge_pages.h).
#include "huge_pages.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace ramtk::tools {

namespace {

bool ImageCommand(int argc, char** argv) {
  if (argc < 2) return false;
  const std::string command = argv[1];
  return command == "scan" || command == "decode" || command == "simulate" || command == "diagnose";
}

bool ThpOnRequest() {
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(mode_file, mode);
  // "[always]": every large mapping gets huge pages already; "[never]": none can.
  return mode.find("[madvise]") != std::string::npos;
}

// What a first touch of fresh memory costs with 4 KiB pages here, ms per MiB: 2 MiB of the
// heap (not yet marked for huge pages), one byte written per page, timed (~1 ms on a host where
// it is cheap). The block goes back to the heap, which keeps it: the scan's first blocks reuse
// the touched pages, so the probe costs nothing in the end (it had been a mapping of its own,
// unmapped again: ~1 ms of every scan thrown away).
double SmallPageFirstTouchMsPerMiB() {
  constexpr std::size_t kProbe = std::size_t{2} << 20, kPage = 4096;
  void* block = std::malloc(kProbe);
  if (!block) return 0;
  volatile char* bytes = static_cast<volatile char*>(block);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < kProbe; i += kPage) bytes[i] = 1;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::free(block);
  return ms / 2.0;
}

}  // namespace

void UseHugePagesForTheHeap(int argc, char** argv) {
#if defined(__SANITIZE_ADDRESS__)
  return;  // the sanitizer's allocator replaces glibc's
#endif
  if (!ImageCommand(argc, argv)) return;
  // One heap for every thread, kept whole: blocks freed by one stage (or one worker thread) are
  // reused by the next instead of fresh pages, and nothing under 2 GiB is mapped on its own.
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, INT_MAX);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
  const char* choice = std::getenv("RAMTK_HUGEPAGES");
  if (choice && std::strcmp(choice, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;  // the user's choice
  if (!ThpOnRequest()) return;
  // Unless asked for (RAMTK_HUGEPAGES=1), only where small pages are dear: on a host whose
  // 4 KiB first touches cost ~0.5 ms/MiB, huge pages saved nothing and their faults sometimes
  // stalled (the kernel compacting memory for them after another process had run); on one where
  // they cost 3-4 ms/MiB they saved a third of a scan (docs/performance.md).
  constexpr double kDearMsPerMiB = 1.5;
  if (!(choice && std::strcmp(choice, "1") == 0) && SmallPageFirstTouchMsPerMiB() < kDearMsPerMiB) return;
  // The heap grown once by kReserve (address space only: no page is touched), marked for huge
  // pages and freed back to the heap's top, from which later blocks are cut.
  constexpr std::size_t kReserve = std::size_t{3} << 29;  // 1.5 GiB
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  void* block = std::malloc(kReserve);
  if (!block) return;
  const auto begin = (reinterpret_cast<std::uintptr_t>(block) + kHuge - 1) & ~(kHuge - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(block) + kReserve) & ~(kHuge - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  std::free(block);
}

}  // namespace ramtk::tools
