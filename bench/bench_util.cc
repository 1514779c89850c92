#include "bench/bench_util.h"

#include <cmath>

#include "cmbrl/core/rng.h"

namespace cmbrl::bench {

void ClassifierData(int count, int dim, std::uint64_t seed, std::vector<float>& safe,
                    std::vector<float>& unsafe) {
  Rng rng(seed);
  const int unsafe_wanted = count / 4;
  int safe_rows = 0, unsafe_rows = 0;
  std::vector<float> row(dim);
  while (safe_rows + unsafe_rows < count) {
    bool violation = false;
    for (int i = 0; i < dim; ++i) row[i] = static_cast<float>(Uniform(rng, -2, 2));
    for (int h = 10; h + 1 < dim; h += 2) violation |= std::hypot(row[h], row[h + 1]) < 0.2;
    if (violation && unsafe_rows < unsafe_wanted) {
      unsafe.insert(unsafe.end(), row.begin(), row.end());
      ++unsafe_rows;
    } else if (!violation && safe_rows < count - unsafe_wanted) {
      safe.insert(safe.end(), row.begin(), row.end());
      ++safe_rows;
    }
  }
}

}  // namespace cmbrl::bench
