#include "cmbrl/run/learner_family.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "cmbrl/core/memory.h"

namespace cmbrl {

double RunMemory::total() const {
  return transitions + labeled_states + ensemble + planning + classifier_fit + policy_networks +
         epoch_batch;
}

std::string RunMemory::Describe() const {
  const auto part = [](const char* name, double bytes) {
    return fmt::format("{} {:.2f} GiB", name, bytes / kGiB);
  };
  if (policy_networks > 0 || epoch_batch > 0) {
    return fmt::format(
        "{}, {}", part("policy_optimisation.policy_hidden and value_hidden", policy_networks),
        part("policy_optimisation.steps_per_epoch (rows x widest layer)", epoch_batch));
  }
  return fmt::format("{}, {}, {}, {}, {}", part("training.transition_capacity", transitions),
                     part("training.safe_capacity and unsafe_capacity", labeled_states),
                     part("ensemble", ensemble),
                     part("planning (population x members x horizon)", planning),
                     part("classifier fit", classifier_fit));
}

bool FamilySheet::Reads(const std::string& section) const {
  return std::find(sections.begin(), sections.end(), section) != sections.end();
}

std::string FamilySheet::ProgressHeader() const {
  return fmt::format("{}", fmt::join(progress_columns, ","));
}

}  // namespace cmbrl
