// The registry of environments: one line per task in registry.cc.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cmbrl/env/env.h"
#include "cmbrl/env/variant.h"

namespace cmbrl {

// Names of every registered task.
std::vector<std::string> EnvNames();

// A new environment for a task ("PointGoal1", ...) and variant. Throws cmbrl::Error naming an
// unknown task and listing the known ones.
std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant = Variant::kPaper,
                             Spawn spawn = Spawn::kStanding);

}  // namespace cmbrl
