// Transparent huge pages for the image-heavy commands (huge_pages.h).
#include "huge_pages.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

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
  if (const char* off = std::getenv("RAMTK_HUGEPAGES"); off && std::strcmp(off, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;  // the user's choice
  if (!ThpOnRequest()) return;
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
