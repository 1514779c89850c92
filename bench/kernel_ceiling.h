// Ceilings on a benchmark's own matrix shapes: the best rate any kernel on this CPU reaches for
// the same chain of batched products, per precision, measured in the same run as the figure.
//
// The candidates are the kernels a CPU build can call: OpenBLAS through LibTorch (fp32),
// LibTorch's own bf16 products, and oneDNN's matmul primitives (fp32 and bf16) with weights
// already in the layout each primitive prefers, both batched (one 3D primitive) and per member
// (2D primitives, as the ensemble's oneDNN backend runs them). The ceiling of a precision is the
// fastest of its candidates; a figure's ratio to it says how much of the hardware the figure uses,
// not how it compares with the library it happens to call.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cmbrl::bench {

// One batched product: `batch` independent (rows x inner) times (inner x cols).
struct ProductShape {
  std::int64_t batch = 1, rows = 1, inner = 1, cols = 1;
  double Flops() const { return 2.0 * batch * rows * inner * cols; }
};

// The products of an ensemble's forward pass over `rows` samples: layer sizes
// [in, hidden..., out], `members` at once.
std::vector<ProductShape> ForwardShapes(std::int64_t members, std::int64_t rows,
                                        const std::vector<std::int64_t>& layer_sizes);

// A kernel timing one pass of a chain of products at one precision.
class ChainKernel {
 public:
  virtual ~ChainKernel() = default;
  virtual std::string name() const = 0;  // "openblas_fp32", "onednn_bf16_per_member", ...
  virtual double Seconds() = 0;          // one pass over every shape
};

// The candidates that run here for "fp32" or "bf16", built for `shapes` (inputs random).
std::vector<std::unique_ptr<ChainKernel>> CeilingKernels(const std::vector<ProductShape>& shapes,
                                                         const std::string& precision);

// Measures every candidate of `precision` (median of `runs` passes each) and keeps the fastest
// as the probe timed beside each run of a figure.
class ShapeCeiling {
 public:
  ShapeCeiling(std::vector<ProductShape> shapes, const std::string& precision, int runs);
  double Flops() const { return flops_; }
  // FLOP/s of the fastest kernel now: its best pass of at least 3 and at least 20 ms of them.
  double Measure();
  // {"<kernel>_gflops": median rate of each candidate, "ceiling_kernel": the fastest}.
  const nlohmann::ordered_json& candidates() const { return candidates_; }

 private:
  double flops_ = 0.0;
  std::vector<std::unique_ptr<ChainKernel>> kernels_;
  ChainKernel* best_ = nullptr;
  nlohmann::ordered_json candidates_;
};

}  // namespace cmbrl::bench
