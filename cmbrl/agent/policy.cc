#include "cmbrl/agent/policy.h"

#include <fmt/ranges.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {

RandomPolicy::RandomPolicy(BoxSpec action_spec, std::uint64_t seed)
    : action_spec_(std::move(action_spec)), rng_(seed) {}

std::vector<double> RandomPolicy::Act(const std::vector<double>& /*observation*/) {
  std::vector<double> action(action_spec_.size());
  for (int i = 0; i < action_spec_.size(); ++i) {
    action[i] = Uniform(rng_, action_spec_.low[i], action_spec_.high[i]);
  }
  return action;
}

const std::vector<std::string>& PolicyNames() {
  static const std::vector<std::string> names = {"random", "zero"};
  return names;
}

std::unique_ptr<Policy> MakePolicy(const std::string& name, const BoxSpec& action_spec,
                                   std::uint64_t seed) {
  if (name == "random") return std::make_unique<RandomPolicy>(action_spec, seed);
  if (name == "zero") return std::make_unique<ZeroPolicy>(action_spec.size());
  Fail("unknown policy '{}'{}: expected one of {}", name, DidYouMean(name, PolicyNames()),
       fmt::join(PolicyNames(), ", "));
}

}  // namespace cmbrl
