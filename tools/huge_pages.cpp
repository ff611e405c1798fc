// Transparent huge pages for the image-heavy commands (huge_pages.h).
#include "huge_pages.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace ramtk::tools {

void ReexecWithHugePages(int argc, char** argv) {
#if defined(__SANITIZE_ADDRESS__)
  return;  // the sanitizer's allocator replaces glibc's: the tunable would do nothing
#endif
  if (argc < 2) return;
  const std::string command = argv[1];
  if (command != "scan" && command != "decode" && command != "simulate" && command != "diagnose") return;
  if (const char* off = std::getenv("RAMTK_HUGEPAGES"); off && std::strcmp(off, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;  // set already (by us or the user)
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(mode_file, mode);
  // "[always]": every large mapping gets huge pages already; "[never]": none can.
  if (mode.find("[madvise]") == std::string::npos) return;
  const std::string value = (tunables && *tunables ? std::string(tunables) + ":" : std::string()) +
                            "glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // exec failed (no /proc): carry on with ordinary pages.
}

}  // namespace ramtk::tools
