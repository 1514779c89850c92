#include "cmbrl/learners/learner_inputs.h"

#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/mujoco_task.h"
#include "cmbrl/env/registry.h"

namespace cmbrl {

std::unique_ptr<Env> MakeRunEnv(const TrainConfig& config, const LearnerInputs& inputs) {
  if (IsDeclaredTask(config.mujoco_task)) {
    return std::make_unique<MujocoTaskEnv>(config.mujoco_task, config.task);
  }
  if (!IsPythonTask(config.task)) return MakeEnv(config.task, config.variant, config.spawn);
  Require(static_cast<bool>(inputs.python_env),
          "task '{}' is an environment given from Python: give it again (cmbrl.train(env=..., "
          "resume=...), cmbrl.load_run(..., env=...)); the command line has none",
          config.task);
  std::unique_ptr<Env> env = inputs.python_env();
  const int observations = env->observation_spec().size();
  const int actions = env->action_spec().size();
  Require(observations == config.observation_size && actions == config.action_size,
          "the environment given for task '{}' observes {} values and takes {} actions, where the "
          "run's environment.observation_size and action_size are {} and {}",
          config.task, observations, actions, config.observation_size, config.action_size);
  return env;
}

}  // namespace cmbrl
