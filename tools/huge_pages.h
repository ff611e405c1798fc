// Transparent huge pages for the image-heavy commands (scan, decode, simulate, diagnose).
//
// A scan touches ~250 MB of fresh buffers; with 4 KiB pages that is ~60 000 page faults, which
// cost 25-35 % of a 1.3 Mpx scan's wall time on the (virtualised) machines measured in
// docs/performance.md. glibc's allocator asks the kernel for 2 MiB pages only when its tunable
// glibc.malloc.hugetlb=1 is set, and tunables are read only when a program starts. So, when the
// kernel's THP mode is "madvise" (huge pages on request) and the tunable is not set, the program
// re-executes itself once with it set. RAMTK_HUGEPAGES=0 turns this off; an explicit
// GLIBC_TUNABLES containing glibc.malloc.hugetlb is respected as given.
#pragma once

namespace ramtk::tools {

// Returns without effect when not applicable; otherwise does not return (exec), except when the
// exec itself fails, in which case the program continues with ordinary pages.
void ReexecWithHugePages(int argc, char** argv);

}  // namespace ramtk::tools
