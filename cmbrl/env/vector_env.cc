#include "cmbrl/env/vector_env.h"

#include <algorithm>
#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

VectorEnv::VectorEnv(std::vector<std::unique_ptr<Env>> envs, int threads,
                     std::chrono::microseconds spin, Autoreset autoreset)
    : envs_(std::move(envs)), autoreset_(autoreset) {
  Require(!envs_.empty(), "a vector of 0 environments: expected at least one");
  Require(threads >= 1, "threads is {}: expected at least 1", threads);
  Require(spin.count() >= 0 && spin.count() <= 1'000'000,
          "spin is {} microseconds: expected 0 to 1000000", spin.count());
  for (const std::unique_ptr<Env>& env : envs_) {
    Require(env->observation_spec().size() == envs_[0]->observation_spec().size() &&
                env->action_spec().size() == envs_[0]->action_spec().size(),
            "environments with {} and {} observations, {} and {} actions: a vector needs one "
            "shape",
            envs_[0]->observation_spec().size(), env->observation_spec().size(),
            envs_[0]->action_spec().size(), env->action_spec().size());
  }
  pool_ = std::make_unique<WorkerPool>(std::min(threads, size()), spin);
  needs_reset_.assign(envs_.size(), 1);
}

std::vector<double> VectorEnv::Reset(std::optional<std::uint64_t> seed) {
  const int n = size();
  const size_t width = static_cast<size_t>(envs_[0]->observation_spec().size());
  std::vector<double> observations(n * width);
  pool_->Run(n, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t k = begin; k < end; ++k) {
      const std::vector<double> first = envs_[static_cast<size_t>(k)]->Reset(
          seed ? std::optional<std::uint64_t>(*seed + static_cast<std::uint64_t>(k))
               : std::nullopt);
      std::copy(first.begin(), first.end(), observations.begin() + k * width);
    }
  });
  needs_reset_.assign(envs_.size(), 0);
  return observations;
}

std::vector<double> VectorEnv::ResetWhere(const std::vector<std::uint8_t>& mask,
                                          const std::vector<std::uint64_t>& seeds) {
  const int n = size();
  Require(mask.size() == static_cast<size_t>(n),
          "reset mask of {} entries for {} environments: expected one per environment",
          mask.size(), n);
  Require(seeds.empty() || seeds.size() == static_cast<size_t>(n),
          "{} seeds for {} environments: expected none or one per environment", seeds.size(), n);
  const size_t width = static_cast<size_t>(envs_[0]->observation_spec().size());
  std::vector<double> observations(n * width, 0.0);
  pool_->Run(n, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t k = begin; k < end; ++k) {
      if (mask[k] == 0) continue;
      const std::vector<double> first = envs_[static_cast<size_t>(k)]->Reset(
          seeds.empty() ? std::nullopt : std::optional<std::uint64_t>(seeds[k]));
      std::copy(first.begin(), first.end(), observations.begin() + k * width);
    }
  });
  for (int k = 0; k < n; ++k) {
    if (mask[k] != 0) needs_reset_[k] = 0;
  }
  return observations;
}

VectorStep VectorEnv::Step(const std::vector<double>& actions,
                           const std::vector<std::uint8_t>& active) {
  const int n = size();
  const size_t width = static_cast<size_t>(envs_[0]->observation_spec().size());
  const size_t action_dim = static_cast<size_t>(envs_[0]->action_spec().size());
  Require(actions.size() == n * action_dim,
          "actions of {} values for {} environments of {} actions: expected {}", actions.size(), n,
          action_dim, n * action_dim);
  Require(active.empty() || active.size() == static_cast<size_t>(n),
          "active mask of {} entries for {} environments: expected none or one per environment",
          active.size(), n);
  const auto steps = [&](size_t k) { return active.empty() || active[k] != 0; };
  // kNextStep: an environment that ended at the last step is reset now, its action unread.
  const auto resets = [&](size_t k) {
    return autoreset_ == Autoreset::kNextStep && steps(k) && needs_reset_[k] != 0;
  };
  for (size_t i = 0; i < actions.size(); ++i) {
    if (!steps(i / action_dim) || resets(i / action_dim)) continue;
    Require(std::isfinite(actions[i]), "action {} of environment {} is {}: expected a finite value",
            i % action_dim, i / action_dim, actions[i]);
  }
  if (autoreset_ == Autoreset::kDisabled) {
    for (size_t k = 0; k < envs_.size(); ++k) {
      Require(!steps(k) || needs_reset_[k] == 0,
              "environment {} is stepped before a reset (its episode ended or never began): "
              "with autoreset disabled, reset it first (ResetWhere)",
              k);
    }
  }
  VectorStep out;
  out.final_observations.assign(n * width, 0.0);
  out.rewards.resize(n);
  out.costs.resize(n);
  out.raw_costs.resize(n);
  out.terminated.resize(n);
  out.truncated.resize(n);
  out.goal_met.resize(n);
  out.cost_hazards.resize(n);
  out.cost_vases_contact.resize(n);
  out.cost_vases_velocity.resize(n);
  out.cost_buttons.resize(n);
  out.cost_gremlins.resize(n);
  out.cost_pillars.resize(n);
  out.cost_out_of_boundary.resize(n);
  out.reset.assign(n, 0);
  out.cost_sums.assign(n, 0.0);
  out.observations.assign(n * width, 0.0);
  const WorkerPool::Work body = [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t k = begin; k < end; ++k) {
      if (!steps(static_cast<size_t>(k))) continue;
      Env& env = *envs_[static_cast<size_t>(k)];
      if (resets(static_cast<size_t>(k))) {
        const std::vector<double> first = env.Reset();
        std::copy(first.begin(), first.end(), out.observations.begin() + k * width);
        out.reset[k] = 1;
        continue;
      }
      StepResult step = env.Step(std::vector<double>(actions.begin() + k * action_dim,
                                                     actions.begin() + (k + 1) * action_dim));
      out.rewards[k] = step.reward;
      out.costs[k] = step.cost;
      out.raw_costs[k] = step.info.raw_cost;
      out.terminated[k] = step.terminated;
      out.truncated[k] = step.truncated;
      out.goal_met[k] = step.info.goal_met;
      out.cost_hazards[k] = step.info.cost_hazards;
      out.cost_vases_contact[k] = step.info.cost_vases_contact;
      out.cost_vases_velocity[k] = step.info.cost_vases_velocity;
      out.cost_buttons[k] = step.info.cost_buttons;
      out.cost_gremlins[k] = step.info.cost_gremlins;
      out.cost_pillars[k] = step.info.cost_pillars;
      out.cost_out_of_boundary[k] = step.info.cost_out_of_boundary;
      out.cost_sums[k] = CostSum(step.info);
      if ((step.terminated || step.truncated) && autoreset_ == Autoreset::kSameStep) {
        std::copy(step.observation.begin(), step.observation.end(),
                  out.final_observations.begin() + k * width);
        step.observation = env.Reset();
      }
      std::copy(step.observation.begin(), step.observation.end(),
                out.observations.begin() + k * width);
    }
  };
  RunStep(n, body);
  if (autoreset_ != Autoreset::kSameStep) {
    for (int k = 0; k < n; ++k) {
      if (out.reset[k] != 0) needs_reset_[k] = 0;
      if (out.terminated[k] != 0 || out.truncated[k] != 0) needs_reset_[k] = 1;
    }
  }
  return out;
}

void VectorEnv::RunStep(int n, const WorkerPool::Work& body) {
  // Adaptive: the first kProbeSteps steps of every kProbeInterval on the pool, the next
  // kProbeSteps on this thread alone; then the faster by the median step.
  const std::int64_t phase = steps_ % kProbeInterval;
  const bool probing = adaptive_ && phase < 2 * kProbeSteps;
  const bool on_pool = probing ? phase < kProbeSteps : on_pool_;
  const auto start = std::chrono::steady_clock::now();
  if (on_pool) {
    pool_->Run(n, body);
  } else {
    body(0, n);
  }
  ++steps_;
  if (!probing) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  (on_pool ? probe_pool_ : probe_inline_).push_back(seconds);
  if (phase + 1 == 2 * kProbeSteps) {
    const auto median = [](std::vector<double>& values) {
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      return values[values.size() / 2];
    };
    on_pool_ = median(probe_pool_) <= median(probe_inline_);
    probe_pool_.clear();
    probe_inline_.clear();
  }
}

void VectorEnv::SetAdaptiveThreads(bool adaptive) {
  adaptive_ = adaptive && pool_->threads() > 1;
  on_pool_ = true;
  steps_ = 0;
  probe_pool_.clear();
  probe_inline_.clear();
}

VectorEnvState VectorEnv::State() const {
  VectorEnvState state;
  for (const std::unique_ptr<Env>& env : envs_) state.envs.push_back(env->State());
  state.needs_reset = needs_reset_;
  return state;
}

void VectorEnv::SetState(const VectorEnvState& state) {
  Require(state.envs.size() == envs_.size() && state.needs_reset.size() == envs_.size(),
          "a vector state of {} environments and {} reset flags for {} environments: expected one "
          "of each per environment",
          state.envs.size(), state.needs_reset.size(), envs_.size());
  const std::vector<std::string> before = State().envs;
  size_t k = 0;
  try {
    for (; k < envs_.size(); ++k) envs_[k]->SetState(state.envs[k]);
  } catch (const Error&) {
    for (size_t j = 0; j < k; ++j) envs_[j]->SetState(before[j]);  // their own: cannot fail
    throw;
  }
  for (k = 0; k < envs_.size(); ++k) needs_reset_[k] = state.needs_reset[k] != 0;
}

}  // namespace cmbrl
