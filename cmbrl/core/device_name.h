// The spelling of a compute device in configs and on the command line: "cpu", "cuda" or "cuda:i".
// Checked here without LibTorch, so that configuration can refuse a misspelt device before any
// model is built; whether the device exists on this machine is ParseDevice's (torch_util.h).
#pragma once

#include <string>

#include "cmbrl/core/check.h"

namespace cmbrl {

// Throws cmbrl::Error naming the key and value unless `name` is "cpu", "cuda" or "cuda:i" (i a
// decimal index of at most 4 digits).
inline void CheckDeviceName(const std::string& name, const char* key = "device") {
  if (name == "cpu" || name == "cuda") return;
  const std::string prefix = "cuda:";
  const std::string index = name.rfind(prefix, 0) == 0 ? name.substr(prefix.size()) : "";
  const bool digits = !index.empty() && index.size() <= 4 &&
                      index.find_first_not_of("0123456789") == std::string::npos;
  Require(digits, "{} '{}' is not a device: expected 'cpu', 'cuda' or 'cuda:N'", key, name);
}

}  // namespace cmbrl
