#include "cmbrl/env/mujoco_handles.h"

#include <array>
#include <cstddef>
#include <cstring>
#include <mutex>
#include <string>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

// mjData's fixed part before its buffers: plain values.
constexpr size_t kDataHeaderBytes = offsetof(mjData, buffer);

// A contact's fields end here; what follows, to sizeof(mjContact), is padding. Its fields are
// numbers then ints, with no padding between them.
constexpr size_t kContactFieldBytes = offsetof(mjContact, efc_address) + sizeof(int);
static_assert(offsetof(mjContact, dim) == offsetof(mjContact, H) + sizeof(mjContact::H),
              "mjContact has padding between its numbers and its ints");

void IgnoreWarning(const char* /*message*/) {}

// mjVFS holds 2000 fixed-size file names (about 2 MB), so it lives on the heap.
struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

}  // namespace

MjModelPtr CompileMjcf(const std::string& mjcf) {
  SilenceMujocoWarnings();
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  constexpr const char* kFileName = "cmbrl_model.xml";
  const int status = mj_makeEmptyFileVFS(vfs.get(), kFileName, static_cast<int>(mjcf.size()));
  Require(status == 0, "MuJoCo could not hold the model in its virtual file system (code {})",
          status);
  const int index = mj_findFileVFS(vfs.get(), kFileName);
  std::memcpy(vfs->filedata[index], mjcf.data(), mjcf.size());

  std::array<char, 1024> error{};
  mjModel* model = mj_loadXML(kFileName, vfs.get(), error.data(), static_cast<int>(error.size()));
  Require(model != nullptr, "MuJoCo could not compile the generated model: {}", error.data());
  return MjModelPtr(model);
}

MjDataPtr MakeMjData(const mjModel& model) {
  mjData* data = mj_makeData(&model);
  Require(data != nullptr, "MuJoCo could not allocate mjData");
  return MjDataPtr(data);
}

void WriteMjDataState(ByteWriter& out, const mjModel& model, const mjData& data) {
  out.WriteBytes(&data, kDataHeaderBytes);
  // The collision code builds each contact on its stack and copies it whole into the buffer,
  // its tail padding with it: bytes of whatever ran before. Written as zeros, so that a state's
  // bytes follow from the model and the steps alone (no step reads them).
  std::string buffer(static_cast<const char*>(data.buffer), static_cast<size_t>(data.nbuffer));
  const std::ptrdiff_t contacts =
      reinterpret_cast<const char*>(data.contact) - static_cast<const char*>(data.buffer);
  const auto capacity = static_cast<std::ptrdiff_t>(model.nconmax);
  Require(contacts >= 0 && contacts + capacity * static_cast<std::ptrdiff_t>(sizeof(mjContact)) <=
                               static_cast<std::ptrdiff_t>(buffer.size()),
          "mjData's contacts lie outside its buffer: expected MuJoCo 2.2's layout");
  for (std::ptrdiff_t i = 0; i < capacity; ++i) {
    char* contact = buffer.data() + contacts + i * static_cast<std::ptrdiff_t>(sizeof(mjContact));
    std::memset(contact + kContactFieldBytes, 0, sizeof(mjContact) - kContactFieldBytes);
  }
  out.WriteBytes(buffer.data(), buffer.size());
}

MjDataStateBytes ReadMjDataState(ByteReader& in, const mjData& data) {
  MjDataStateBytes state;
  state.header = in.ReadBytes(kDataHeaderBytes);
  state.buffer = in.ReadBytes(static_cast<size_t>(data.nbuffer));
  return state;
}

void ApplyMjDataState(const MjDataStateBytes& state, mjData& data) {
  std::memcpy(static_cast<void*>(&data), state.header.data(), kDataHeaderBytes);
  std::memcpy(data.buffer, state.buffer.data(), state.buffer.size());
}

int RequireMjId(const mjModel& model, mjtObj type, const std::string& name) {
  const int id = mj_name2id(&model, type, name.c_str());
  Require(id >= 0, "the MuJoCo model has no object named '{}' of type {}", name,
          static_cast<int>(type));
  return id;
}

void SilenceMujocoWarnings() {
  static std::once_flag once;
  std::call_once(once, [] { mju_user_warning = IgnoreWarning; });
}

}  // namespace cmbrl
