#include "cmbrl/core/torch_util.h"

#include <dlfcn.h>

#include <sstream>

#include <ATen/CPUGeneratorImpl.h>
#include <ATen/Context.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/device_name.h"
#include "cmbrl/core/files.h"

namespace cmbrl {

at::Generator MakeCpuGenerator(std::uint64_t seed) {
  return at::make_generator<at::CPUGeneratorImpl>(seed);
}

at::Generator MakeGenerator(const torch::Device& device, std::uint64_t seed) {
  if (device.is_cpu()) return MakeCpuGenerator(seed);
  const int index = device.has_index() ? device.index() : 0;
  // Through the context, whose name for it holds from LibTorch 1.13 to 2.x (the CUDA hooks'
  // own getter was renamed).
  at::Generator generator =
      at::globalContext().defaultGenerator(torch::Device(torch::kCUDA, index)).clone();
  generator.set_current_seed(seed);
  return generator;
}

torch::Device ParseDevice(const std::string& name, const char* key) {
  CheckDeviceName(name, key);
  torch::Device device(torch::kCPU);
  try {
    device = torch::Device(name);
  } catch (const c10::Error&) {
    Fail("{} '{}' is not a device: expected 'cpu', 'cuda' or 'cuda:N'", key, name);
  }
  if (device.is_cuda()) {
    Require(torch::cuda::is_available(),
            "{} '{}' asks for CUDA, but this LibTorch has no CUDA or sees no GPU: use 'cpu'", key,
            name);
    const int count = static_cast<int>(torch::cuda::device_count());
    Require(!device.has_index() || device.index() < count,
            "{} '{}': only {} CUDA device(s) are visible", key, name, count);
    // Tensors report the index they live on ('cuda:0'), which a bare 'cuda' lacks: name the
    // device the way tensors will, so device checks compare like with like.
    if (!device.has_index()) device = torch::Device(torch::kCUDA, 0);
  }
  return device;
}

std::vector<double> ToDoubles(const torch::Tensor& t) {
  const torch::Tensor host = t.to(torch::kCPU, torch::kDouble).contiguous();
  return std::vector<double>(host.data_ptr<double>(), host.data_ptr<double>() + host.numel());
}

void CheckFloatTensor(const torch::Tensor& t, const char* what, std::int64_t last_dim,
                      const torch::Device& device) {
  Require(t.defined(), "{} is an undefined tensor", what);
  Require(t.scalar_type() == torch::kFloat, "{} has dtype {}: expected float32", what,
          std::string(c10::toString(t.scalar_type())));
  Require(t.dim() >= 1 && t.size(-1) == last_dim, "{} has shape {}: expected (..., {})", what,
          c10::str(t.sizes()), last_dim);
  Require(t.device() == device, "{} is on {}: expected {}", what, t.device().str(), device.str());
}

void CheckFinite(const torch::Tensor& t, const char* what) {
  const torch::Tensor bad = torch::logical_not(torch::isfinite(t));
  if (!bad.any().item<bool>()) return;
  const std::int64_t flat = bad.flatten().nonzero()[0][0].item<std::int64_t>();
  const std::int64_t columns = t.dim() > 0 ? t.size(-1) : 1;
  Fail("{} has a non-finite value {} at row {}, column {}: expected finite numbers", what,
       t.flatten()[flat].item<float>(), flat / columns, flat % columns);
}

ScopedSingleThreadedMath::ScopedSingleThreadedMath() : torch_threads_(at::get_num_threads()) {
  at::set_num_threads(1);
  // OpenBLAS's thread controls, looked up at run time (LibTorch may use another BLAS).
  using GetThreads = int (*)();
  const auto get =
      reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  blas_set_threads_ =
      reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (get != nullptr && blas_set_threads_ != nullptr) {
    blas_threads_ = get();
    blas_set_threads_(1);
  }
}

ScopedSingleThreadedMath::~ScopedSingleThreadedMath() {
  at::set_num_threads(torch_threads_);
  if (blas_threads_ > 0) blas_set_threads_(blas_threads_);
}

void SaveArchive(torch::serialize::OutputArchive& archive, const std::string& path) {
  std::ostringstream bytes;
  try {
    archive.save_to(bytes);
  } catch (const c10::Error& error) {
    Fail("could not write '{}': {}", path, error.what_without_backtrace());
  }
  WriteFile(path, bytes.str());
}

void SaveTensor(const torch::Tensor& tensor, const std::string& path) {
  std::ostringstream bytes;
  try {
    torch::save(tensor, bytes);
  } catch (const c10::Error& error) {
    Fail("could not write '{}': {}", path, error.what_without_backtrace());
  }
  WriteFile(path, bytes.str());
}

}  // namespace cmbrl
