// RAII ownership of MuJoCo's model and data, and loading a model from an MJCF string.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

namespace cmbrl {

struct MjModelDeleter {
  void operator()(mjModel* model) const { mj_deleteModel(model); }
};
struct MjDataDeleter {
  void operator()(mjData* data) const { mj_deleteData(data); }
};

using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// Compiles an MJCF document held in memory. Throws cmbrl::Error with MuJoCo's message (and the
// line it names) when the document does not compile. Thread-safe.
MjModelPtr CompileMjcf(const std::string& mjcf);

// Allocates data for a model. Throws if MuJoCo cannot allocate it.
MjDataPtr MakeMjData(const mjModel& model);

// Id of a named object of the given type; throws cmbrl::Error naming it when it is missing.
int RequireMjId(const mjModel& model, mjtObj type, const std::string& name);

// MuJoCo prints its warnings and writes them to MUJOCO_LOG.TXT by default; the library reads the
// warning counters in mjData instead. Installs a silent handler once; safe to call repeatedly.
void SilenceMujocoWarnings();

}  // namespace cmbrl
