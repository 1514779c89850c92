#include "bench/ceiling.h"

#include <torch/cuda.h>

#include <chrono>
#include <cstdlib>
#include <vector>

#include "bench/bench_util.h"
#include "cmbrl/core/process_setup.h"

namespace cmbrl::bench {

void Synchronize(const torch::Device& device) {
  if (device.is_cuda()) torch::cuda::synchronize(device.index());
}

namespace {

// Median FLOP/s of `runs` products at one precision.
double MedianRate(const torch::Device& device, const std::string& precision, int runs) {
  CeilingProbe probe(device, precision);
  std::vector<double> rates;
  for (int i = 0; i < runs; ++i) rates.push_back(probe.Measure());
  return Median(rates);
}

}  // namespace

void GemmCeilings(const torch::Device& device, int runs, const FigureSink& emit) {
  const std::int64_t n = device.is_cuda() ? 8192 : 2048;
  const int gemm_runs = std::max(5, runs);
  nlohmann::ordered_json line = {{"bench", "ceiling"}, {"what", "gemm"}, {"n", n},
                                 {"device", device.str()}};
  line["fp32_gflops"] = MedianRate(device, "fp32", gemm_runs) / 1e9;
  if (device.is_cuda()) {
    line["tf32_gflops"] = MedianRate(device, "tf32", gemm_runs) / 1e9;
    line["bf16_gflops"] = MedianRate(device, "bf16", gemm_runs) / 1e9;
  } else {
    const BlasKernelInfo blas = DetectBlasKernels();
    line["blas_core"] = blas.core;
    const char* coretype = std::getenv("OPENBLAS_CORETYPE");
    line["blas_coretype"] = coretype != nullptr ? coretype : "";
    line["blas_restarted"] = BlasRestarted();
    line["blas_core_best_for_cpu"] = blas.best_core;
    line["torch_threads"] = at::get_num_threads();
  }
  emit(line);
}

CeilingProbe::CeilingProbe(const torch::Device& device, const std::string& precision)
    : device_(device), tf32_(precision == "tf32" && device.is_cuda()) {
  const std::int64_t n = device.is_cuda() ? 8192 : 2048;
  const torch::ScalarType dtype = precision == "bf16" ? torch::kBFloat16 : torch::kFloat;
  const auto options = torch::TensorOptions(device).dtype(dtype);
  a_ = torch::randn({n, n}, options);
  b_ = torch::randn({n, n}, options);
  c_ = torch::empty({n, n}, options);
  Measure();  // warm-up
}

double CeilingProbe::Measure() {
  const torch::NoGradGuard no_grad;
  auto& context = at::globalContext();
  const bool tf32_before = context.allowTF32CuBLAS();
  if (device_.is_cuda()) context.setAllowTF32CuBLAS(tf32_);
  const std::int64_t n = a_.size(0);
  const auto start = std::chrono::steady_clock::now();
  torch::mm_out(c_, a_, b_);
  Synchronize(device_);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (device_.is_cuda()) context.setAllowTF32CuBLAS(tf32_before);
  return 2.0 * n * n * n / seconds;
}

}  // namespace cmbrl::bench
