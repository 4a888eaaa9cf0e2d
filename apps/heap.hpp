#pragma once
// The heap policy of programs that fit many times in a row (epuck2-fit, the benchmarks).

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace epuck2::app {

/// Keeps freed heap memory in the process for the next fit instead of handing it back.
///
/// glibc gives the top of the heap back to the system as soon as more than 128 KiB of it is free
/// (M_TRIM_THRESHOLD), and serves blocks above 128 KiB by mmap (M_MMAP_THRESHOLD, raised only
/// after such a block is freed). A fit of a few thousand rows frees more than that at its end
/// (Ceres' Jacobian, its evaluation scratch, the recorded residuals), so each following fit
/// faulted the same pages in again: 18-30 page faults per battery cubic fit, which then took up
/// to 65 % longer (166 against 101 us for 3207 rows), depending on what happened to be allocated
/// before (bench/README.md). With both
/// thresholds raised, the pages stay mapped and are reused. Call once, at the start of main; it
/// changes nothing but where freed memory waits (the process keeps up to its peak heap until it
/// exits). A no-op on other C libraries.
inline void keep_freed_heap() {
#if defined(__GLIBC__)
  constexpr int kTrimThreshold = 256 << 20;  // 256 MiB
  constexpr int kMmapThreshold = 32 << 20;   // 32 MiB, glibc's largest on 64-bit systems
  mallopt(M_TRIM_THRESHOLD, kTrimThreshold);
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
#endif
}

}  // namespace epuck2::app
