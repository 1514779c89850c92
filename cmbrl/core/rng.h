// Explicit, seeded randomness. Every stochastic function of the library takes an Rng& derived
// from the run seed; nothing reads a global generator or std::random_device.
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>

#include "cmbrl/core/check.h"

namespace cmbrl {

// The library's generator. Its output sequence is fixed by the C++ standard, so a seed gives
// the same numbers with every compiler and standard library.
using Rng = std::mt19937_64;

// Uniform double in [0, 1) from the top 53 bits of one draw. std::uniform_real_distribution is
// not used because its algorithm differs between standard libraries, which would break
// bit-for-bit reproducibility across platforms.
inline double Uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Uniform double in [low, high).
inline double Uniform(Rng& rng, double low, double high) {
  return low + (high - low) * Uniform01(rng);
}

// A generator's whole state as text (the standard's stream form), and back: what an
// environment's checkpoint keeps. RngFromText throws cmbrl::Error for text that is not one.
inline std::string RngText(const Rng& rng) {
  std::ostringstream out;
  out << rng;
  return out.str();
}
inline Rng RngFromText(const std::string& text) {
  std::istringstream in(text);
  Rng restored;
  in >> restored;
  Require(!in.fail(), "not a generator state: expected the text GeneratorState() wrote");
  return restored;
}

// Mixes a seed with a stream index into an independent seed (SplitMix64 finaliser), so that one
// run seed can feed several generators (environment, planner, model) without overlap.
inline std::uint64_t DeriveSeed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace cmbrl
