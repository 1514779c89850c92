// The environments of the tasks listed in task_list.h (one line each there), built on MuJoCo.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cmbrl/env/env.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/env/variant.h"

namespace cmbrl {

// A new environment for a task ("PointGoal1", ...) and variant. Throws cmbrl::Error naming an
// unknown task and listing the known ones.
std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant = Variant::kPaper,
                             Spawn spawn = Spawn::kStanding);

// `count` new environments of one task (for a VectorEnv). The first two are made, the memory the
// second holds measured (the resident memory it added; the first also pays for what a process
// makes once),
// and the rest made only when `count` of them fit the machine's memory (core/memory.h). Throws cmbrl::Error for a count below 1, and naming the count and
// each environment's size when they would not fit.
std::vector<std::unique_ptr<Env>> MakeEnvs(const std::string& task, Variant variant, Spawn spawn,
                                           int count);

}  // namespace cmbrl
