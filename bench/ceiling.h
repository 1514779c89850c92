// The ceilings the `cmbrl bench` figures are held against: matrix-product rates measured in the
// same run, on the device of the figures.
#pragma once

#include <string>

#include "bench/bench_util.h"

#include <torch/torch.h>

namespace cmbrl::bench {

// One figure with the median FLOP/s of a large square matrix product (n = 2048 on a
// CPU, 8192 on CUDA): fp32 always; on CUDA also TF32 and bf16; on the CPU the BLAS kernels in use.
void GemmCeilings(const torch::Device& device, int runs, const FigureSink& emit);

// One matrix product of the ceiling's size at one precision ("fp32", "tf32" on CUDA, "bf16"),
// to measure just before each run of a figure: on a shared machine a ceiling measured seconds
// earlier can be off by 2x, a ratio of back-to-back measurements much less.
class CeilingProbe {
 public:
  CeilingProbe(const torch::Device& device, const std::string& precision);
  double Measure();  // FLOP/s of one product, device synchronised
 private:
  torch::Device device_;
  bool tf32_;
  torch::Tensor a_, b_, c_;
};

// Waits for the device's queued work (a no-op on the CPU).
void Synchronize(const torch::Device& device);

}  // namespace cmbrl::bench
