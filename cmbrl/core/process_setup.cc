#include "cmbrl/core/process_setup.h"

#include <dlfcn.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>

#include "cmbrl/core/cpu_features.h"

namespace cmbrl {
namespace {

constexpr const char* kRestartMarker = "CMBRL_BLAS_RESTARTED";

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

bool BlasKernelInfo::slow() const {
  if (core.empty() || best_core.empty()) return false;
  // OpenBLAS cores with AVX2 (or better) kernels; anything else leaves most of the CPU unused.
  static constexpr std::array<const char*, 8> kFast = {"haswell",    "skylakex", "cooperlake",
                                                       "sapphirerapids", "zen",  "skylake",
                                                       "broadwell",  "icelake"};
  const std::string name = Lower(core);
  return std::none_of(kFast.begin(), kFast.end(), [&](const char* fast) { return name == fast; });
}

BlasKernelInfo DetectBlasKernels() {
  BlasKernelInfo info;
  // Looked up at run time so that the program neither links nor needs OpenBLAS itself.
  using CoreName = char* (*)();
  if (auto* corename = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"))) {
    if (const char* name = corename()) info.core = name;
  }
  using GetThreads = int (*)();
  if (auto* threads =
          reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))) {
    info.threads = threads();
  }
  if (CpuHasAvx512Bf16()) {
    info.best_core = "Cooperlake";
  } else if (CpuHasAvx512()) {
    info.best_core = "SkylakeX";
  } else if (CpuHasAvx2()) {
    info.best_core = "Haswell";
  }
  return info;
}

bool BlasRestarted() { return std::getenv(kRestartMarker) != nullptr; }

void RestartWithFastBlasIfNeeded(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr || std::getenv(kRestartMarker) != nullptr) {
    return;  // the user chose, or this process is already the restart
  }
  const BlasKernelInfo info = DetectBlasKernels();
  if (!info.slow()) return;
  setenv("OPENBLAS_CORETYPE", info.best_core.c_str(), 1);
  setenv(kRestartMarker, "1", 1);
  execv("/proc/self/exe", argv);
  // The restart failed (no /proc, say): go on with the slow kernels rather than not at all.
  unsetenv("OPENBLAS_CORETYPE");
}

void KeepLargeAllocationsInHeap() {
  constexpr int kLarge = 1 << 30;  // bytes: served from the heap below this size
  mallopt(M_MMAP_THRESHOLD, kLarge);
  mallopt(M_TRIM_THRESHOLD, kLarge);
}

void PrepareProcessForSpeed(char** argv) {
  RestartWithFastBlasIfNeeded(argv);
  KeepLargeAllocationsInHeap();
}

}  // namespace cmbrl
