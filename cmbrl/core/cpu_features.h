// The vector instructions this CPU offers the kernels (trees, oneDNN, OpenBLAS's choice), looked
// up once. One home for the question, so that every kernel and every run record agree.
#pragma once

#include <string>

namespace cmbrl {

#if defined(__x86_64__) && defined(__GNUC__)
// AVX-512 as the kernels use it: F, BW, VL and DQ together.
inline bool CpuHasAvx512() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
  }();
  return has;
}

inline bool CpuHasAvx512Bf16() {
  static const bool has = CpuHasAvx512() && __builtin_cpu_supports("avx512bf16");
  return has;
}

// AVX2 with FMA.
inline bool CpuHasAvx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return has;
}
#else
inline bool CpuHasAvx512() { return false; }
inline bool CpuHasAvx512Bf16() { return false; }
inline bool CpuHasAvx2() { return false; }
#endif

// The widest of them: "avx512-bf16", "avx512", "avx2", or "" for an older or other CPU.
inline std::string CpuIsaName() {
  if (CpuHasAvx512Bf16()) return "avx512-bf16";
  if (CpuHasAvx512()) return "avx512";
  if (CpuHasAvx2()) return "avx2";
  return "";
}

}  // namespace cmbrl
