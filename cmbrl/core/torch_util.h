// Small LibTorch helpers shared by the models and the planners.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

// A CPU generator seeded from `seed`. Random numbers for models are drawn on the CPU and moved
// to the device, so a seed gives the same draws on every device.
at::Generator MakeCpuGenerator(std::uint64_t seed);

// A generator on `device` seeded from `seed`: LibTorch's CPU generator, or a clone of the CUDA
// default generator (through ATen's hooks, so the CPU-only build compiles too).
at::Generator MakeGenerator(const torch::Device& device, std::uint64_t seed);

// Parses "cpu", "cuda" or "cuda:i"; throws cmbrl::Error naming the key and value when the string
// is not a device or the device is not available in this build or machine.
torch::Device ParseDevice(const std::string& name, const char* key = "device");

// The values of `t`, any dtype on any device, as doubles in row-major order (one host copy).
std::vector<double> ToDoubles(const torch::Tensor& t);

// Throws cmbrl::Error naming `what` unless `t` is (…, last_dim) float32 on `device`.
void CheckFloatTensor(const torch::Tensor& t, const char* what, std::int64_t last_dim,
                      const torch::Device& device);

// Throws cmbrl::Error naming `what` and the first bad element when `t` has a NaN or infinity.
// One host synchronisation.
void CheckFinite(const torch::Tensor& t, const char* what);

// Saves an archive (or a tensor) to `path` through memory and core/files.h: LibTorch writing a
// file itself ends the process (an exception from a destructor) when the disk fills. Throws
// cmbrl::Error naming the file and the cause.
void SaveArchive(torch::serialize::OutputArchive& archive, const std::string& path);
void SaveTensor(const torch::Tensor& tensor, const std::string& path);

// While alive, LibTorch's CPU operations and OpenBLAS (when the process has it) run on the
// calling thread alone; the thread counts before are restored at destruction. For independent
// pieces of math run side by side on threads of their own: each gives the numbers it gives on
// one thread, whatever the number of cores. Process-wide: one at a time, from one thread.
class ScopedSingleThreadedMath {
 public:
  ScopedSingleThreadedMath();
  ~ScopedSingleThreadedMath();
  ScopedSingleThreadedMath(const ScopedSingleThreadedMath&) = delete;
  ScopedSingleThreadedMath& operator=(const ScopedSingleThreadedMath&) = delete;

 private:
  int torch_threads_;
  int blas_threads_ = 0;                        // 0 when the process has no OpenBLAS
  void (*blas_set_threads_)(int) = nullptr;     // OpenBLAS's, looked up once
};

}  // namespace cmbrl
