// Transparent huge pages for the image-heavy commands (scan, decode, simulate, diagnose).
//
// A scan touches ~100-500 MB of fresh buffers; with 4 KiB pages that is tens of thousands of page
// faults, which cost 25-35 % of a 1.3 Mpx scan's wall time on the (virtualised) machines
// measured in docs/performance.md. When the kernel's THP mode is "madvise" (huge pages on
// request), the heap is grown once by 1.5 GiB of address space (no page touched) marked
// MADV_HUGEPAGE, and every block is cut from that one heap: glibc is told to keep one arena for
// all threads, to map nothing on its own below 2 GiB and never to trim (re-executing with
// GLIBC_TUNABLES=glibc.malloc.hugetlb=1 would pay the start-up of 46 shared libraries twice). The
// reserve is made only where a 2 MiB probe finds 4 KiB first touches dear (>= 1.5 ms/MiB): on a
// host where they are cheap the huge pages gain nothing and their faults sometimes stall. RAMTK_HUGEPAGES=1 makes the reserve
// without the probe, RAMTK_HUGEPAGES=0 never (the heap settings stay either way); an explicit
// GLIBC_TUNABLES containing glibc.malloc.hugetlb is respected.
#pragma once

namespace ramtk::tools {

// Call first in main, before any other thread exists. Without effect for other commands.
void UseHugePagesForTheHeap(int argc, char** argv);

}  // namespace ramtk::tools
