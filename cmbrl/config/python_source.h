// A run's Python parts declared by name in its config (section python), so that the command
// line, sweeps and evaluation can make them as cmbrl.train(env=..., reward=..., termination=...)
// is given them: each is "module:attribute" (attribute dotted for a nested one), imported with
// the folders of `path` first on Python's sys.path. Plain data.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

struct PythonSourceOptions {
  std::string env;          // a zero-argument factory (class or function) of the environment
  std::string reward;       // reward(states, actions, next_states): objective.reward python
  std::string termination;  // termination(states, actions, next_states): ... termination python
  // Folders put first on sys.path, in order; relative ones are taken from the folder of the
  // config file that names them (a run's config.yaml records them absolute).
  std::vector<std::string> path;
};

// Whether the section declares anything.
inline bool DeclaresPython(const PythonSourceOptions& p) {
  return !p.env.empty() || !p.reward.empty() || !p.termination.empty();
}

// Throws cmbrl::Error naming the first key whose value is not "module:attribute" (Python
// identifiers, dotted) or an empty folder.
void ValidatePythonSourceOptions(const PythonSourceOptions& options);

// "module.attribute()": what a run's task records after "python:" for a declared environment,
// as cmbrl.train(env=module.attribute) names it.
std::string DeclaredEnvName(const std::string& declared);

// "python:module.attribute()": the task of a run on the environment `declared` names (the
// config's task when it names none of its own).
std::string DeclaredEnvTask(const std::string& declared);

}  // namespace cmbrl
