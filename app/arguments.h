// Checks of numbers and paths given on the command line: every number option gets a bound and a
// message that names the option, the text and the range, instead of being wrapped (-1 as a seed)
// or clamped (a budget past 2^63) by the conversion; every path a message that names its fault.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>

namespace cmbrl::app {

// A validator that accepts only the decimal integers in [low, high] (no sign for a low of 0 or
// more, no exponent, no fraction): "is '-1': expected an integer from 0 to 100".
CLI::Validator IntegerIn(std::int64_t low, std::int64_t high);

// The same for seeds: 0 to 2^64 - 1.
CLI::Validator SeedInteger();

// A validator that accepts only finite decimal numbers in [low, high] (no "nan" or "inf"):
// "is 'nan': expected a number from 0 to 86400".
CLI::Validator NumberIn(double low, double high);

// Validators of paths given on the command line: they say what is wrong with the path, the
// system's cause included ("'loop' cannot be read: Too many levels of symbolic links", "'x' is a
// folder: expected a file"), where CLI11's ExistingFile says "File does not exist" for any of it.
CLI::Validator ExistingFile();
CLI::Validator ExistingFolder();

// Budgets of agent or environment steps: 1 to 10^10.
inline constexpr std::int64_t kMaxSteps = 10'000'000'000;

}  // namespace cmbrl::app
