#include "cmbrl/learners/learner_inputs.h"

#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/mujoco_task.h"
#include "cmbrl/env/previous_action_env.h"
#include "cmbrl/env/registry.h"

namespace cmbrl {
namespace {

PythonInputsMaker& Maker() {
  static PythonInputsMaker maker;
  return maker;
}

}  // namespace

void SetPythonInputsMaker(PythonInputsMaker maker) { Maker() = std::move(maker); }

LearnerInputs WithDeclaredPython(const TrainConfig& config, LearnerInputs given) {
  const PythonSourceOptions& declared = config.python;
  PythonSourceOptions wanted;  // what is declared and not given
  if (!given.python_env) wanted.env = declared.env;
  if (!given.python_reward && config.objective.reward == "python") wanted.reward = declared.reward;
  if (!given.python_termination && config.objective.termination == "python") {
    wanted.termination = declared.termination;
  }
  if (!DeclaresPython(wanted)) return given;
  wanted.path = declared.path;
  Require(static_cast<bool>(Maker()),
          "the config declares Python parts (python.env '{}', python.reward '{}', "
          "python.termination '{}'), and this cmbrl was built without Python "
          "(CMBRL_BUILD_PYTHON=OFF)",
          declared.env, declared.reward, declared.termination);
  LearnerInputs made = Maker()(wanted);
  if (!wanted.env.empty()) {
    given.python_env = std::move(made.python_env);
    given.python_render_env = std::move(made.python_render_env);
    given.python_task = std::move(made.python_task);
    given.observation_size = made.observation_size;
    given.action_size = made.action_size;
  }
  if (!wanted.reward.empty()) given.python_reward = std::move(made.python_reward);
  if (!wanted.termination.empty()) given.python_termination = std::move(made.python_termination);
  given.python_functions = given.python_functions.empty() || made.python_functions.empty()
                               ? given.python_functions + made.python_functions
                               : given.python_functions + ", " + made.python_functions;
  return given;
}

void RecordPythonEnv(TrainConfig& config, const LearnerInputs& inputs) {
  if (!inputs.python_env) return;
  if (config.python.env.empty()) {
    config.task = inputs.python_task;
  } else {
    const std::string declared = DeclaredEnvTask(config.python.env);
    Require(declared == inputs.python_task,
            "the config declares python.env '{}' ({}), and another environment is given ({}): "
            "give one of them",
            config.python.env, declared, inputs.python_task);
  }
  config.observation_size = inputs.observation_size;
  config.action_size = inputs.action_size;
}

namespace {

// The run's environment as its task makes it, before environment.previous_action.
std::unique_ptr<Env> MakeTaskEnv(const TrainConfig& config, const LearnerInputs& inputs) {
  if (IsDeclaredTask(config.mujoco_task)) {
    return std::make_unique<MujocoTaskEnv>(config.mujoco_task, config.task);
  }
  if (!IsPythonEnvTask(config)) return MakeEnv(config.task, config.variant, config.spawn);
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

}  // namespace

std::unique_ptr<Env> MakeRunEnv(const TrainConfig& config, const LearnerInputs& inputs) {
  std::unique_ptr<Env> env = MakeTaskEnv(config, inputs);
  if (!config.previous_action) return env;
  return std::make_unique<PreviousActionEnv>(std::move(env));
}

}  // namespace cmbrl
