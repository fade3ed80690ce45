// The run driver's stepper: it takes the same steps as step() itself, keeps the state
// before a step only on request, puts it back after a divergence, and sums the steps.
#include <gtest/gtest.h>

#include "physics/stepper.h"
#include "test_meshes.h"

namespace tissu {
namespace {

testing::Sheet falling_sheet(Integrator integrator, double dt) {
  return testing::cotton_sheet(0.3, 6, integrator, dt, 5);
}

TEST(Stepper, TakesTheSameStepsAsStepItself) {
  for (Integrator integrator : {Integrator::SymplecticEuler, Integrator::BackwardEuler}) {
    const double dt = integrator == Integrator::BackwardEuler ? 1.0 / 60.0 : 1e-4;
    testing::Sheet direct = falling_sheet(integrator, dt);
    testing::Sheet driven = falling_sheet(integrator, dt);
    Workspace ws;
    Stepper stepper(driven.model, driven.state);
    for (int k = 0; k < 5; ++k) {
      ASSERT_FALSE(step(direct.model, direct.state, ws));
      ASSERT_FALSE(stepper.advance(k % 2 == 0));
    }
    EXPECT_EQ(driven.state.x, direct.state.x);
    EXPECT_EQ(driven.state.v, direct.state.v);
    EXPECT_EQ(driven.state.step, 5);
    EXPECT_EQ(stepper.totals().steps, 5);
    if (integrator == Integrator::BackwardEuler) {
      EXPECT_GE(stepper.totals().newton_iterations, 5);
    } else {
      EXPECT_EQ(stepper.totals().newton_iterations, 0);
    }
  }
}

TEST(Stepper, KeepsTheStateBeforeOnRequestAndPutsItBack) {
  testing::Sheet s = falling_sheet(Integrator::SymplecticEuler, 1e-4);
  Stepper stepper(s.model, s.state);
  ASSERT_FALSE(stepper.advance(false));
  EXPECT_FALSE(stepper.has_before());
  const State start = s.state;
  ASSERT_FALSE(stepper.advance(true));
  ASSERT_TRUE(stepper.has_before());
  EXPECT_EQ(stepper.before().x, start.x);
  EXPECT_EQ(stepper.before().v, start.v);
  EXPECT_EQ(stepper.before().step, start.step);
  EXPECT_NE(s.state.x, start.x);
  stepper.restore_before();
  EXPECT_EQ(s.state.x, start.x);
  EXPECT_EQ(s.state.v, start.v);
  EXPECT_EQ(s.state.t, start.t);
  EXPECT_EQ(s.state.step, start.step);
  EXPECT_FALSE(stepper.has_before());
}

}  // namespace
}  // namespace tissu
