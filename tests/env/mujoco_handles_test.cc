#include "cmbrl/env/mujoco_handles.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/env/registry.h"

namespace cmbrl {
namespace {

// A box dropped on a plane: contacts, so that part of the buffer's contact and constraint
// capacity is written by a step and the rest is not.
constexpr const char* kBoxOnPlane = R"(<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body pos="0 0 0.12"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
</mujoco>)";

// Fills 256 KiB of the stack below the caller with `fill`, where the next call's frames go.
__attribute__((noinline)) void DirtyStack(char fill) {
  volatile char block[256 << 10];
  for (size_t i = 0; i < sizeof(block); ++i) block[i] = fill;
}

// Fills a block of `size` bytes with `fill` and frees it; the compiler may not leave it out.
void FillAndFree(size_t size, char fill) {
  char* block = static_cast<char*>(std::malloc(size));
  ASSERT_NE(block, nullptr);
  std::memset(block, fill, size);
  asm volatile("" : : "r"(block) : "memory");
  std::free(block);
}

std::string StateBytes(const mjModel& model, const mjData& data) {
  ByteWriter out;
  WriteMjDataState(out, model, data);
  return out.Take();
}

// A saved state is mjData's whole buffer (WriteMjDataState), parts of which no step writes (the
// contact and constraint capacity beyond what a step fills, padding). They must hold nothing of
// what the memory held before, or a checkpoint's bytes would depend on it: MuJoCo 2.2.2's reset,
// which making data runs too, clears the whole buffer; this test keeps that so.
TEST(MujocoHandlesTest, AResetLeavesNothingOfWhatTheBufferHeld) {
  const MjModelPtr model = CompileMjcf(kBoxOnPlane);
  MjDataPtr data = MakeMjData(*model);
  constexpr unsigned char kStale = 0xAB;
  std::memset(data->buffer, kStale, static_cast<size_t>(data->nbuffer));
  mj_resetData(model.get(), data.get());
  const auto* bytes = static_cast<const unsigned char*>(data->buffer);
  std::int64_t stale = 0;  // runs of 8 stale bytes: a value of the model's never looks so
  for (int i = 0; i + 8 <= data->nbuffer; i += 8) {
    stale += std::all_of(bytes + i, bytes + i + 8, [](unsigned char b) { return b == kStale; });
  }
  EXPECT_EQ(stale, 0) << "8-byte runs of the old bytes, of " << data->nbuffer / 8;

  // And two data of one model, stepped alike, give the same state bytes.
  MjDataPtr other = MakeMjData(*model);
  for (int step = 0; step < 50; ++step) {
    mj_step(model.get(), data.get());
    mj_step(model.get(), other.get());
  }
  EXPECT_GT(data->ncon, 0);
  EXPECT_EQ(StateBytes(*model, *data), StateBytes(*model, *other));
}

// The same at a task's size, through the environment's State(): two environments made where
// memory filled with different bytes was freed save the same state after the same steps.
TEST(MujocoHandlesTest, ATasksStateDoesNotDependOnWhatTheHeapHeld) {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // freed memory stays for the next allocations
  const auto state_after_freeing = [](char fill) {
    FillAndFree(64 << 20, fill);
    std::unique_ptr<Env> env = MakeEnv("PointGoal1");
    env->Reset(7);
    for (int step = 0; step < 20; ++step) env->Step({0.5, 0.3});
    std::string state = env->State();
    return std::make_pair(std::move(env), std::move(state));
  };
  // The first stays alive, so the second is made in memory of its own.
  const auto first = state_after_freeing(static_cast<char>(0xAB));
  const auto second = state_after_freeing(static_cast<char>(0x55));
  EXPECT_TRUE(first.second == second.second) << "the state bytes differ";
}

// And what the stack held: MuJoCo copies each contact whole from its stack, padding included.
// Two environments stepped alike over a stack filled with different bytes save the same state.
TEST(MujocoHandlesTest, ATasksStateDoesNotDependOnWhatTheStackHeld) {
  const auto state_over = [](char fill) {
    std::unique_ptr<Env> env = MakeEnv("PointGoal1");
    env->Reset(7);
    for (int step = 0; step < 60; ++step) {  // into the hazards and vases: contacts
      DirtyStack(fill);
      env->Step({0.9, 0.9});
    }
    return env->State();
  };
  EXPECT_TRUE(state_over(static_cast<char>(0xAB)) == state_over(static_cast<char>(0x11)))
      << "the state bytes differ";
}

}  // namespace
}  // namespace cmbrl
