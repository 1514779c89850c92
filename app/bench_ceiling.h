// The ceilings the `cmbrl bench` figures are held against: matrix-product rates measured in the
// same run, on the device of the figures.
#pragma once

#include <string>

#include <torch/torch.h>

namespace cmbrl::app {

// FLOP/s of a large square matrix product (n = 2048 on a CPU, 8192 on CUDA): fp32 always; on
// CUDA also TF32 and bf16 (0 where not measured). Prints one JSON line with the rates and the
// BLAS kernels in use.
struct GemmCeilings {
  double fp32 = 0.0;
  double tf32 = 0.0;
  double bf16 = 0.0;
};

GemmCeilings MeasureGemmCeilings(const torch::Device& device, int runs);

// Waits for the device's queued work (a no-op on the CPU).
void Synchronize(const torch::Device& device);

}  // namespace cmbrl::app
