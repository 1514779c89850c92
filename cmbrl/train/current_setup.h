// The numerics setup of this process (run/run_sessions.h): what it asks of the libraries that do
// the arithmetic (LibTorch, OpenBLAS, MuJoCo, XGBoost), so it lives above them, beside the
// trainer that records it for every session of a run.
#pragma once

#include <string>

#include "cmbrl/run/run_sessions.h"

namespace cmbrl {

// This process's setup, for a run on `device`.
NumericsSetup CurrentNumericsSetup(const std::string& device);

}  // namespace cmbrl
