// The heap on transparent huge pages (app/huge_page_heap.hpp), with glibc's malloc parameters: a
// large top pad makes one sbrk cover the reservation, and the range is advised while it is still
// untouched. glibc's own switch for this (GLIBC_TUNABLES=glibc.malloc.hugetlb=1) can only be set
// from the environment before the process starts.

#include "app/huge_page_heap.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <system_error>
#include <thread>

namespace thermnet::app {

namespace {

/// The reserved heap's huge-page-aligned range [first, top), set by reserve_huge_page_heap.
std::uintptr_t heap_first = 0, heap_top = 0;

} // namespace

void reserve_huge_page_heap(std::size_t bytes) {
  constexpr std::uintptr_t huge_page = std::uintptr_t{2} << 20;
  constexpr int largest_heap_block = 32 << 20; // glibc's upper limit for M_MMAP_THRESHOLD
  constexpr int default_top_pad = 128 << 10;   // glibc's DEFAULT_TOP_PAD
  constexpr std::size_t largest_setting = std::numeric_limits<int>::max(); // mallopt takes an int
  constexpr std::size_t block_size = std::size_t{1} << 20;
  // Trimming starts when the free top exceeds this: it must stay above the reservation.
  const std::size_t trim = std::min(2 * bytes, largest_setting);
  if (bytes == 0 || bytes + block_size >= trim) return;
  if (::mallopt(M_MMAP_THRESHOLD, largest_heap_block) == 0) return;
  if (::mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim)) == 0) return;
  if (::mallopt(M_TOP_PAD, static_cast<int>(bytes)) == 0) return;
  // A block larger than the free top of the heap makes malloc extend it by the block plus the pad.
  void* block = std::malloc(block_size);
  void* end = ::sbrk(0);
  const auto start = reinterpret_cast<std::uintptr_t>(block);
  ::mallopt(M_TOP_PAD, default_top_pad);
  if (!block) return;
  std::free(block);
  if (end == reinterpret_cast<void*>(-1)) return;
  const auto first = (start + huge_page - 1) & ~(huge_page - 1);
  const auto top = reinterpret_cast<std::uintptr_t>(end) & ~(huge_page - 1);
  if (first < top) {
    ::madvise(reinterpret_cast<void*>(first), top - first, MADV_HUGEPAGE);
    heap_first = first, heap_top = top;
  }
}

void prefault_heap_for(std::uintmax_t netlist_bytes) {
#ifdef MADV_POPULATE_WRITE
  static constexpr std::uintptr_t step = std::uintptr_t{2} << 20;
  constexpr std::uintmax_t smallest = std::uintmax_t{1} << 20, heap_per_byte = 16;
  if (heap_first == 0 || netlist_bytes < smallest) return;
  const std::uintmax_t bytes = heap_per_byte * netlist_bytes;
  const std::uintptr_t end = heap_first + std::min<std::uintptr_t>(bytes, heap_top - heap_first);
  try {
    std::thread([first = heap_first, end] {
      // Pages already touched by the loading thread are skipped by the kernel; a failure (an
      // old kernel: EINVAL) ends the thread, the loading thread then faults pages in itself.
      for (std::uintptr_t p = first; p < end; p += step)
        if (::madvise(reinterpret_cast<void*>(p), std::min(step, end - p), MADV_POPULATE_WRITE) !=
            0)
          return;
    }).detach();
  } catch (const std::system_error&) {
    // no thread: the loading thread faults pages in itself
  }
#else
  (void)netlist_bytes;
#endif
}

} // namespace thermnet::app
