// Process-wide settings that make the numerical work fast, for programs to apply first thing in
// main(): the BLAS kernels and the allocator.
//
// OpenBLAS picks its matrix kernels once, when the library loads, from the CPU it detects. On
// the virtual CPUs we run on it often detects an ancient core ("Prescott") and runs about 5x
// slower (measured on the development machines). The environment variable OPENBLAS_CORETYPE overrides the
// detection, but only before the library loads, so a program has to restart itself to use it.
#pragma once

#include <string>

namespace cmbrl {

// What OpenBLAS runs on: its core name ("" when the process has no OpenBLAS) and the kernel
// set this CPU supports best ("" when the CPU has no AVX2).
struct BlasKernelInfo {
  std::string core;       // openblas_get_corename(), e.g. "Prescott", "Haswell", "SkylakeX"
  std::string best_core;  // "Cooperlake", "SkylakeX" or "Haswell" from the CPU's features
  int threads = 0;        // openblas_get_num_threads() (0 when the process has no OpenBLAS)
  bool slow() const;      // OpenBLAS runs a core without the AVX2 kernels the CPU supports
};

BlasKernelInfo DetectBlasKernels();

// Call first thing in main(). When OpenBLAS runs slow kernels and the user has not set
// OPENBLAS_CORETYPE, sets it to best_core and re-executes the program with the same arguments
// (once: a marker variable stops a loop). Returns only when no restart was needed or the
// restart failed. The process keeps its pid, arguments and open files.
void RestartWithFastBlasIfNeeded(char** argv);

// Whether this process is such a restart.
bool BlasRestarted();

// Keeps freed large blocks in the heap instead of returning them to the system: glibc hands
// blocks over 32 MiB back at once, so every training step's weight-sized tensors were fresh,
// zero-filled pages (5% of a paper-sized epoch in page faults).
void KeepLargeAllocationsInHeap();

// Both of the above.
void PrepareProcessForSpeed(char** argv);

}  // namespace cmbrl
