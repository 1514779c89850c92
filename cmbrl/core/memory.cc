#include "cmbrl/core/memory.h"

#include <unistd.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

std::uint64_t PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0
             ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size)
             : 0;
}

void RequireMemory(double bytes, const std::string& what, const std::string& remedy) {
  const double available = static_cast<double>(PhysicalMemoryBytes());
  Require(available <= 0 || bytes <= kPlannedMemoryShare * available,
          "{} would need about {:.1f} GiB, more than {:.0f}% of this machine's {:.1f} GiB: {}",
          what, bytes / kGiB, 100 * kPlannedMemoryShare, available / kGiB, remedy);
}

}  // namespace cmbrl
