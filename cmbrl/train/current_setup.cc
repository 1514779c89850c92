#include "cmbrl/train/current_setup.h"

#include <ATen/Parallel.h>
#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <torch/version.h>
#include <xgboost/c_api.h>

#include <fstream>

#include "cmbrl/core/build_info.h"
#include "cmbrl/core/cpu_features.h"
#include "cmbrl/core/process_setup.h"
#include "cmbrl/models/onednn_forward.h"

namespace cmbrl {
namespace {

std::string CpuModelName() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const size_t start = line.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? std::string() : line.substr(start);
  }
  return "";
}

}  // namespace

NumericsSetup CurrentNumericsSetup(const std::string& device) {
  NumericsSetup setup;
  setup.cmbrl = fmt::format("{} ({})", CmbrlVersion(), CmbrlCommit());
  setup.cpu = CpuModelName();
  setup.cpu_isa = CpuIsaName();
  const BlasKernelInfo blas = DetectBlasKernels();
  setup.blas_core = blas.core;
  setup.blas_threads = blas.threads;
  setup.torch_threads = at::get_num_threads();
  setup.libtorch = TORCH_VERSION;
  setup.mujoco = mj_versionString();
  int major = 0, minor = 0, patch = 0;
  XGBoostVersion(&major, &minor, &patch);
  setup.xgboost = fmt::format("{}.{}.{}", major, minor, patch);
  setup.onednn = OnednnVersion();
  setup.device = device;
  return setup;
}

}  // namespace cmbrl
