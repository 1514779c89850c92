#include "cmbrl/env/variant.h"

#include "cmbrl/core/check.h"

namespace cmbrl {

std::string VariantName(Variant variant) {
  return variant == Variant::kPaper ? "paper" : "standard";
}

Variant ParseVariant(const std::string& name) {
  if (name == "paper") return Variant::kPaper;
  if (name == "standard") return Variant::kStandard;
  Fail(
      "unknown variant '{}': expected 'paper' (the paper's modified tasks) or 'standard' "
      "(Safety-Gymnasium's stock tasks)",
      name);
}

}  // namespace cmbrl
