#include "cmbrl/env/previous_action_env.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <vector>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/env/registry.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

template <typename T>
std::vector<T> Head(const std::vector<T>& values, int size) {
  return {values.begin(), values.begin() + size};
}
std::vector<double> Tail(const std::vector<double>& values, int size) {
  return {values.end() - size, values.end()};
}

// The observation is the wrapped one's followed by the action's box, named previous_action_<i>.
TEST(PreviousActionEnvTest, ObservesTheWrappedObservationThenTheActionsBox) {
  for (const char* task : {"PointGoal1", "CarGoal2"}) {
    SCOPED_TRACE(task);
    std::unique_ptr<Env> plain = MakeEnv(task);
    PreviousActionEnv env(MakeEnv(task));
    const BoxSpec& inner = plain->observation_spec();
    const BoxSpec& box = env.observation_spec();
    ASSERT_EQ(box.size(), inner.size() + 2);
    EXPECT_EQ(Head(box.names, inner.size()), inner.names);
    EXPECT_EQ(box.names[inner.size()], "previous_action_0");
    EXPECT_EQ(box.names[inner.size() + 1], "previous_action_1");
    EXPECT_EQ(box.low[inner.size()], plain->action_spec().low[0]);
    EXPECT_EQ(box.high[inner.size() + 1], plain->action_spec().high[1]);
    EXPECT_EQ(PreviousActionOffset(box, 2), inner.size());
    EXPECT_EQ(PreviousActionOffset(inner, 2), -1);
    EXPECT_EQ(env.max_episode_steps(), plain->max_episode_steps());
    EXPECT_EQ(env.agent_step_seconds(), plain->agent_step_seconds());
  }
}

// Zeros after a reset, then the action the environment ran: clipped to the box, as the
// environment clips it; the rest of every step is the unwrapped environment's, bit for bit.
TEST(PreviousActionEnvTest, AppendsTheClippedActionAndChangesNothingElse) {
  std::unique_ptr<Env> plain = MakeEnv("CarGoal1");
  PreviousActionEnv env(MakeEnv("CarGoal1"));
  const int size = plain->observation_spec().size();
  const std::vector<double> first = env.Reset(7);
  EXPECT_EQ(Head(first, size), plain->Reset(7));
  EXPECT_THAT(Tail(first, 2), ElementsAre(0.0, 0.0));
  const std::vector<std::vector<double>> actions = {{0.3, -0.2}, {2.0, -5.0}, {-0.7, 0.9}};
  for (const std::vector<double>& action : actions) {
    const StepResult wrapped = env.Step(action);
    const StepResult expected = plain->Step(action);
    EXPECT_EQ(Head(wrapped.observation, size), expected.observation);
    EXPECT_EQ(wrapped.reward, expected.reward);
    EXPECT_EQ(wrapped.cost, expected.cost);
    EXPECT_EQ(wrapped.terminated, expected.terminated);
    EXPECT_EQ(wrapped.truncated, expected.truncated);
    EXPECT_EQ(Tail(wrapped.observation, 2), env.previous_action());
  }
  EXPECT_THAT(env.previous_action(), ElementsAre(-0.7, 0.9));
  env.Step({2.0, -5.0});
  EXPECT_THAT(env.previous_action(), ElementsAre(1.0, -1.0));  // the box is [-1, 1]
  EXPECT_THAT(Tail(env.Reset(), 2), ElementsAre(0.0, 0.0));
  // A bad action is the environment's to refuse; the previous action stays.
  env.Step({0.5, 0.25});
  EXPECT_THAT(ErrorMessage([&] { env.Step({0.5}); }), HasSubstr("action"));
  EXPECT_THAT(env.previous_action(), ElementsAre(0.5, 0.25));
}

// State() holds the previous action: restored into another such environment, the next steps
// are the same; bytes of another kind, or of another number of actions, change nothing.
TEST(PreviousActionEnvTest, ItsStateRestoresThePreviousActionToo) {
  PreviousActionEnv env(MakeEnv("PointGoal1"));
  env.Reset(3);
  env.Step({0.4, -0.6});
  const std::string state = env.State();
  ASSERT_TRUE(env.TryState().has_value());
  EXPECT_EQ(*env.TryState(), state);
  const StepResult next = env.Step({0.1, 0.2});

  PreviousActionEnv other(MakeEnv("PointGoal1"));
  other.Reset(99);
  other.SetState(state);
  EXPECT_THAT(other.previous_action(), ElementsAre(0.4, -0.6));
  EXPECT_EQ(other.Step({0.1, 0.2}).observation, next.observation);

  PreviousActionEnv untouched(MakeEnv("PointGoal1"));
  const std::vector<double> start = untouched.Reset(5);
  EXPECT_THAT(ErrorMessage([&] { untouched.SetState(MakeEnv("PointGoal1")->State()); }),
              HasSubstr("not an environment's with its previous action"));
  ByteWriter three;  // the same layout with a previous action of 3 components
  three.Write(std::string("cmbrl-previous-action-v1"));
  three.Write<std::uint64_t>(3);
  const double values[3] = {0.1, 0.2, 0.3};
  three.WriteBytes(values, sizeof(values));
  three.Write(MakeEnv("PointGoal1")->State());
  EXPECT_THAT(ErrorMessage([&] { untouched.SetState(three.Take()); }),
              HasSubstr("previous action of 3 components, and this environment takes 2"));
  EXPECT_THAT(ErrorMessage([&] { untouched.SetState(state.substr(0, 50)); }),
              HasSubstr("is damaged: it ends early"));
  EXPECT_THAT(ErrorMessage([&] { untouched.SetState(state + "x"); }),
              HasSubstr("1 bytes more than expected"));
  EXPECT_THAT(untouched.previous_action(), ElementsAre(0.0, 0.0));
  PreviousActionEnv fresh(MakeEnv("PointGoal1"));
  fresh.Reset(5);
  EXPECT_EQ(untouched.Step({0.3, 0.3}).observation, fresh.Step({0.3, 0.3}).observation);
}

TEST(PreviousActionEnvTest, RefusesToWrapTwiceOrNothing) {
  EXPECT_THAT(ErrorMessage([] { PreviousActionEnv env(nullptr); }),
              HasSubstr("no environment to wrap"));
  EXPECT_THAT(ErrorMessage([] {
                PreviousActionEnv env(std::make_unique<PreviousActionEnv>(MakeEnv("PointGoal1")));
              }),
              HasSubstr("already observes its previous action"));
  BoxSpec broken;
  broken.names = {"x", "previous_action_0", "y"};
  broken.low = broken.high = {0, 0, 0};
  EXPECT_THAT(ErrorMessage([&] { PreviousActionOffset(broken, 2); }),
              HasSubstr("has no 'previous_action_1' after it"));
}

}  // namespace
}  // namespace cmbrl
