// Which version of the Safety Gym Goal tasks an environment re-creates.
#pragma once

#include <string>

namespace cmbrl {

enum class Variant {
  kPaper,     // the modified suite the paper's code ran (facts B0, B1): the default
  kStandard,  // Safety-Gymnasium's stock tasks (facts A1 to A6)
};

// "paper" or "standard".
std::string VariantName(Variant variant);

// Parses "paper" or "standard"; throws cmbrl::Error naming the value otherwise.
Variant ParseVariant(const std::string& name);

}  // namespace cmbrl
