#pragma once
/// Backing the process's heap with transparent huge pages where the system allows it on request
/// (`/sys/kernel/mm/transparent_hugepage/enabled` = madvise, the usual default). Loading a large
/// model allocates hundreds of MB in small blocks; with 4 KiB pages every first touch is a page
/// fault, and on virtual machines those faults were half of `simulate`'s CPU time.

#include <cstddef>

namespace thermnet::cli {

/// Grows the heap once by `bytes` (address space only: memory is used as it is touched), asks the
/// kernel for huge pages over it (madvise MADV_HUGEPAGE) and keeps it: blocks up to 32 MiB come
/// from the heap and freed memory is not returned to the system. Does nothing if any step fails
/// or `bytes` is outside what mallopt can express (1 MiB to 2 GiB less 1 MiB).
void reserve_huge_page_heap(std::size_t bytes);

} // namespace thermnet::cli
