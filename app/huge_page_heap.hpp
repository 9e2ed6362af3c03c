#pragma once
/// Backing the process's heap with transparent huge pages where the system allows it on request
/// (`/sys/kernel/mm/transparent_hugepage/enabled` = madvise, the usual default). Loading a large
/// model allocates hundreds of MB in small blocks; with 4 KiB pages every first touch is a page
/// fault, and on virtual machines those faults were half of `simulate`'s CPU time.

#include <cstddef>
#include <cstdint>

namespace thermnet::app {

/// Grows the heap once by `bytes` (address space only: memory is used as it is touched), asks the
/// kernel for huge pages over it (madvise MADV_HUGEPAGE) and keeps it: blocks up to 32 MiB come
/// from the heap and freed memory is not returned to the system. Does nothing if any step fails
/// or `bytes` is outside what mallopt can express (1 MiB to 2 GiB less 1 MiB).
void reserve_huge_page_heap(std::size_t bytes);

/// Before a netlist of `netlist_bytes` is loaded: from 1 MiB on, makes the first 16 bytes of the
/// reserved heap per byte of netlist resident on a background thread (a large netlist's load
/// touches about that much: bench/results/front_end.md), by madvise MADV_POPULATE_WRITE 2 MiB at
/// a time (contents unchanged), so that the kernel zeroes those fresh pages on the other core
/// instead of in the loading thread's page faults. Returns at once; does nothing without a
/// reserved heap or when the kernel lacks MADV_POPULATE_WRITE (Linux < 5.14).
void prefault_heap_for(std::uintmax_t netlist_bytes);

} // namespace thermnet::app
