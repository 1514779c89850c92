// What a learner may be given beside its config by the program that trains or loads the run:
// parts that a config file cannot hold (Python functions and environments). Empty from the
// command line.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace cmbrl {

class Env;
class RewardTerm;
class TerminationTerm;
struct PythonSourceOptions;
struct TrainConfig;

struct LearnerInputs {
  // The planning objective's reward term of a run whose objective.reward is "python".
  std::function<std::unique_ptr<RewardTerm>()> python_reward;
  // Its termination term, where objective.termination is "python".
  std::function<std::unique_ptr<TerminationTerm>()> python_termination;
  // A new environment of a run whose task is given from Python ("python:..."), once per copy the
  // learner needs (the model-free learners step several).
  std::function<std::unique_ptr<Env>()> python_env;
  // A new one that draws itself (Env::Frame), for pictures of an evaluation: the factory called
  // with render_mode="rgb_array", Gymnasium's convention; empty where the factory takes none.
  std::function<std::unique_ptr<Env>()> python_render_env;
  // What was given, "env=module.make_env(), reward=module.f, termination=module.g": each
  // session records it.
  std::string python_functions;
  // The environment given: its task ("python:" + what made it) and sizes, read from the first
  // one made (0 where none is given).
  std::string python_task;
  int observation_size = 0;
  int action_size = 0;
};

// What makes the Python parts a config declares (section python): the imported Python module
// sets one, and the command line one that starts an interpreter of its own. It returns the
// declared env, reward and termination as LearnerInputs; it throws cmbrl::Error naming a
// module or attribute that cannot be imported.
using PythonInputsMaker = std::function<LearnerInputs(const PythonSourceOptions&)>;
void SetPythonInputsMaker(PythonInputsMaker maker);

// `given`, completed with what `config` declares in its python section and `given` lacks (a
// Python function given wins over the name declared). Throws cmbrl::Error where something is
// declared and this program has no maker (a build without Python).
LearnerInputs WithDeclaredPython(const TrainConfig& config, LearnerInputs given);

// Records the environment given in `inputs` as the run's task and sizes (task, environment.
// observation_size and action_size); nothing where none is given. Throws cmbrl::Error where
// `config` declares another environment.
void RecordPythonEnv(TrainConfig& config, const LearnerInputs& inputs);

// A new environment of the run's task: built in; declared in its config (mujoco_task, which
// checks every name against its model); or made by inputs.python_env for a task given from
// Python. Throws cmbrl::Error when a Python task's environment is not given, or when its sizes
// differ from those the run recorded (environment.observation_size, action_size). With
// environment.previous_action, its observation ends with the previous action (PreviousActionEnv).
std::unique_ptr<Env> MakeRunEnv(const TrainConfig& config, const LearnerInputs& inputs);

}  // namespace cmbrl
