#include <sys/mman.h>

#include <cstdint>

#include "grid/field.hpp"

namespace biota::grid {

void advise_huge_pages(void* p, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  // Whole 4 KiB pages only; the block start is 2 MiB aligned by the allocator.
  const std::size_t page = 4096;
  const auto start = reinterpret_cast<std::uintptr_t>(p);
  if (start % page != 0) return;
  madvise(p, (bytes + page - 1) / page * page, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace biota::grid
