#include "cmbrl/learners/mpc/mpc_parts.h"

#include <fmt/format.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/env/previous_action_env.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/env/tasks/task_spec.h"
#include "cmbrl/models/action_echo_dynamics.h"

namespace cmbrl {

namespace {

// objective.reward: learned. The reward model's prediction for each predicted step, as a cost.
class LearnedRewardTerm final : public RewardTerm {
 public:
  explicit LearnedRewardTerm(const StepModel& model) : model_(model) {}
  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override {
    return -model_.Predict(StepInputs(states, actions, next_states));
  }
  bool reads_states_and_actions() const override { return true; }

 private:
  const StepModel& model_;
};

// objective.termination: learned. The termination model's probability that each predicted step
// ends the episode: the objective's sums then weigh each step by the probability that the
// episode is still going, their expectation under the model.
class LearnedTerminationTerm final : public TerminationTerm {
 public:
  explicit LearnedTerminationTerm(const StepModel& model) : model_(model) {}
  torch::Tensor Terminal(const torch::Tensor& states, const torch::Tensor& actions,
                         const torch::Tensor& next_states) const override {
    return model_.Predict(StepInputs(states, actions, next_states));
  }

 private:
  const StepModel& model_;
};

}  // namespace

MpcPartSeeds RunSeeds(std::uint64_t seed) {
  return {DeriveSeed(seed, kEnsembleSeedStream), DeriveSeed(seed, kClassifierSeedStream),
          DeriveSeed(seed, kPlannerSeedStream), DeriveSeed(seed, kRewardModelSeedStream),
          DeriveSeed(seed, kTerminationModelSeedStream)};
}

std::unique_ptr<RewardTerm> RewardTermFor(const TrainConfig& config, const LearnerInputs& inputs,
                                          const StepModel* learned, const BoxSpec* observation) {
  if (config.objective.reward == "learned") {
    Require(learned != nullptr, "objective.reward is 'learned': the run has no reward model");
    return std::make_unique<LearnedRewardTerm>(*learned);
  }
  if (config.objective.reward == "python") {
    Require(static_cast<bool>(inputs.python_reward),
            "objective.reward is 'python': the run plans with a reward function given from "
            "Python (cmbrl.train(..., reward=f), cmbrl.load_run(..., reward=f)); the command "
            "line has none");
    return inputs.python_reward();
  }
  if (IsDeclaredTask(config.mujoco_task)) {  // its own form, on its sensor's components
    const MujocoTaskOptions& task = config.mujoco_task;
    Require(observation != nullptr, "a declared task's reward needs its observation's names");
    const int offset = observation->IndexOf(task.reward_sensor + "_0");
    int width = 0;
    while (offset + width < observation->size() &&
           observation->names[offset + width] == fmt::format("{}_{}", task.reward_sensor, width)) {
      ++width;
    }
    return std::make_unique<ObservationRewardTerm>(task.reward, offset, width, task.reward_target,
                                                   task.reward_axis);
  }
  // "analytic": the task's own form (validated with the config), with the task's lidar range and
  // circle from its spec. An env from Python has no spec: a stock task's of the family whose
  // lidars the form reads (Safety-Gymnasium's, 3 m; Circle's 6 m).
  const std::string form = AnalyticRewardForm(config);
  NavigationTaskSpec spec;
  if (IsPythonTask(config.task)) {
    TaskEntry stock;
    stock.family = form == kCircleLidarSpeedReward ? TaskFamily::kCircle : TaskFamily::kGoal;
    spec = MakeNavigationTaskSpec(stock, Variant::kStandard);
  } else {
    spec = NavigationTaskSpecByName(config.task, config.variant);
  }
  return MakeAnalyticReward(
      form, config.objective,
      observation != nullptr ? observation->names : std::vector<std::string>{},
      LidarGeometry{spec.lidar_max_dist, spec.circle_radius});
}

std::unique_ptr<TerminationTerm> TerminationTermFor(const TrainConfig& config,
                                                    const LearnerInputs& inputs,
                                                    const StepModel* learned) {
  if (config.objective.termination == "none") return nullptr;
  if (config.objective.termination == "learned") {
    Require(learned != nullptr,
            "objective.termination is 'learned': the run has no termination model");
    return std::make_unique<LearnedTerminationTerm>(*learned);
  }
  // "python" (validated with the config).
  Require(static_cast<bool>(inputs.python_termination),
          "objective.termination is 'python': the run plans with a termination function given "
          "from Python (cmbrl.train(..., termination=f), cmbrl.load_run(..., termination=f)); "
          "the command line has none");
  return inputs.python_termination();
}

PlannerSettings PlannerSettingsFor(const TrainConfig& config, int action_dim) {
  PlannerSettings settings = config.planning;
  settings.problem.action_dim = action_dim;
  return settings;
}

MpcParts AssembleMpc(const TrainConfig& config, const MpcPartSeeds& seeds,
                     const LearnerInputs& inputs) {
  MpcParts parts;
  parts.env = MakeRunEnv(config, inputs);
  const int state_dim = parts.env->observation_spec().size();
  const int action_dim = parts.env->action_spec().size();
  parts.ensemble =
      std::make_unique<EnsembleDynamics>(state_dim, action_dim, config.ensemble, seeds.ensemble);
  const int previous_action = PreviousActionOffset(parts.env->observation_spec(), action_dim);
  if (previous_action >= 0) {
    parts.planning_dynamics =
        std::make_unique<ActionEchoDynamics>(*parts.ensemble, previous_action);
  }
  parts.classifier =
      std::make_unique<XgbCostModel>(state_dim, config.classifier, seeds.classifier);
  if (config.objective.reward == "learned") {
    parts.reward_model = std::make_unique<StepModel>(
        StepSignal::kReward, 2 * state_dim + action_dim, config.reward_model, seeds.reward_model);
  }
  if (config.objective.termination == "learned") {
    parts.termination_model =
        std::make_unique<StepModel>(StepSignal::kTermination, 2 * state_dim + action_dim,
                                    config.termination_model, seeds.termination_model);
  }
  parts.agent = std::make_unique<MpcAgent>(
      parts.planner_dynamics(), *parts.classifier, config.planner,
      PlannerSettingsFor(config, action_dim), config.objective,
      RewardTermFor(config, inputs, parts.reward_model.get(), &parts.env->observation_spec()),
      seeds.planner, TerminationTermFor(config, inputs, parts.termination_model.get()));
  return parts;
}

}  // namespace cmbrl
