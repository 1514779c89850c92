// RAII ownership of MuJoCo's model and data, loading a model from an MJCF string, and the data's
// state as bytes.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>
#include <string_view>

namespace cmbrl {

class ByteReader;  // core/binary_io.h
class ByteWriter;

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

// mjData's state, for an environment's State(): its fixed part before the buffers (sizes,
// counters, diagnostics, time: plain values) and its main buffer (positions, velocities, warm
// start, contacts, sensors), so that the next mj_step continues bit for bit. The scratch stack
// is not state. Data of one model have buffers of one layout. The contacts' padding is written
// as zeros: the bytes depend on nothing but the model and the steps.
void WriteMjDataState(ByteWriter& out, const mjModel& model, const mjData& data);

// The bytes WriteMjDataState wrote, read from `in` and checked against the sizes of `data` (of the
// same model), not yet applied: an environment reads and checks all its state before it changes
// anything. Views into the reader's bytes.
struct MjDataStateBytes {
  std::string_view header;  // mjData up to its buffer pointer
  std::string_view buffer;  // its main buffer, nbuffer bytes
};
MjDataStateBytes ReadMjDataState(ByteReader& in, const mjData& data);

// Copies read bytes into `data`; its pointers stay its own (the header ends before them).
void ApplyMjDataState(const MjDataStateBytes& state, mjData& data);

// MuJoCo prints its warnings and writes them to MUJOCO_LOG.TXT by default; the library reads the
// warning counters in mjData instead. Installs a silent handler once; safe to call repeatedly.
void SilenceMujocoWarnings();

}  // namespace cmbrl
