// How much memory a process may plan to hold, so that a size too large for the machine is an
// error naming what asked for it, before anything is allocated, never an allocator's stack trace
// or the kernel's OOM killer.
#pragma once

#include <cstdint>
#include <string>

namespace cmbrl {

// This machine's physical memory in bytes (0 when unknown).
std::uint64_t PhysicalMemoryBytes();

// The share of the machine's memory one cmbrl process may plan to hold.
inline constexpr double kPlannedMemoryShare = 0.8;

inline constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// Throws cmbrl::Error "<what> would need about X GiB, more than 80% of this machine's Y GiB:
// <remedy>" when `bytes` is more than that share (nothing when the machine's memory is unknown).
void RequireMemory(double bytes, const std::string& what, const std::string& remedy);

}  // namespace cmbrl
