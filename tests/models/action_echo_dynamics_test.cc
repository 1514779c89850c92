#include "cmbrl/models/action_echo_dynamics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "tests/error_message.h"
#include "tests/planning/fake_models.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using testing::LinearDynamics;

// The predicted state is the wrapped model's, except the A components from the offset, which
// are the actions taken: in both calls, for every member and sample.
TEST(ActionEchoDynamicsTest, WritesTheActionsIntoThePreviousActionComponents) {
  LinearDynamics model(3);
  ActionEchoDynamics echo(model, 4);  // components 4 and 5 of LinearDynamics' are unused
  EXPECT_EQ(echo.state_dim(), 8);
  EXPECT_EQ(echo.action_dim(), 2);
  EXPECT_EQ(echo.ensemble_size(), 3);
  const torch::Tensor states = torch::randn({3, 5, 8});
  const torch::Tensor actions = torch::rand({3, 5, 2}) * 2 - 1;
  for (const torch::Tensor& next :
       {echo.Predict(states, actions), echo.PredictUnchecked(states, actions)}) {
    const torch::Tensor plain = model.Predict(states, actions);
    EXPECT_TRUE(torch::equal(next.narrow(2, 4, 2), actions));
    EXPECT_TRUE(torch::equal(next.narrow(2, 0, 4), plain.narrow(2, 0, 4)));
    EXPECT_TRUE(torch::equal(next.narrow(2, 6, 2), plain.narrow(2, 6, 2)));
  }
}

TEST(ActionEchoDynamicsTest, RefusesAnOffsetOutsideTheState) {
  LinearDynamics model(1);
  EXPECT_THAT(ErrorMessage([&] { ActionEchoDynamics echo(model, 7); }),
              ::testing::HasSubstr("components 7 to 8 does not fit a state of 8"));
  EXPECT_THAT(ErrorMessage([&] { ActionEchoDynamics echo(model, -1); }),
              ::testing::HasSubstr("does not fit"));
  ActionEchoDynamics last(model, 6);
  EXPECT_EQ(last.offset(), 6);
}

}  // namespace
}  // namespace cmbrl
