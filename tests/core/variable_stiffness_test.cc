// The variable-stiffness section (ScopeParams::variable_stiffness): the level the input
// names scales the section's EI, and the level is part of the state's snapshot.
#include <cmath>

#include <gtest/gtest.h>

#include "core/scope_state.h"
#include "core/scope_step.h"
#include "step.h"

namespace colosim {
namespace {

// A scope along +x, d2 along +z, under gravity along -z: 0.45 m inserted (a cantilever
// clamped at the anus), section 0.1-0.45 m from the tip with levels 1x, 2x, 3x.
ScopeModel sectionScope() {
  ScopeParams p;
  p.variable_stiffness.from_m = 0.1;
  p.variable_stiffness.to_m = 0.45;
  p.variable_stiffness.levels = {1.0, 2.0, 3.0};
  p.variable_stiffness.default_level = 0;
  return buildScopeModel(p, Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -9.81));
}

// The tip's sag under gravity at a level (-1: none named), after insertion and settling [m].
double tipSag(const ScopeModel& m, int level) {
  ScopeState s = makeScopeState(m);
  HandleInput in;
  in.stiffness_level = level;
  for (int n = 1; n <= 3000; ++n) {
    in.insertion_m = 0.45 * std::min(1.0, n / 1000.0);
    stepScope(m, s, in, kDt);
  }
  EXPECT_EQ(s.input.stiffness_level, level);  // the step keeps the level it was given
  return -tipPosition(m, s).z();
}

TEST(VariableStiffness, TheSectionJointsAreThoseWithinItsArclength) {
  const ScopeModel m = sectionScope();
  // Joint k at (k+1) h: 0.105 m (k = 6) is the first within 0.1 m, 0.45 m (k = 29) the last.
  EXPECT_EQ(m.variable_first_joint, 6);
  EXPECT_EQ(m.variable_end_joint, 30);
  HandleInput in;
  in.stiffness_level = 2;
  EXPECT_EQ(bendingStiffnessFactor(m, 5, in), 1.0);
  EXPECT_EQ(bendingStiffnessFactor(m, 6, in), 3.0);
  EXPECT_EQ(bendingStiffnessFactor(m, 29, in), 3.0);
  EXPECT_EQ(bendingStiffnessFactor(m, 30, in), 1.0);
  in.stiffness_level = 9;  // past the last: the last
  EXPECT_EQ(stiffnessLevelOf(m, in), 2);
  in.stiffness_level = -1;  // the default
  EXPECT_EQ(stiffnessLevelOf(m, in), 0);
}

TEST(VariableStiffness, StifferLevelsSagLess) {
  const ScopeModel m = sectionScope();
  const double sag0 = tipSag(m, 0), sag1 = tipSag(m, 1), sag2 = tipSag(m, 2);
  EXPECT_DOUBLE_EQ(tipSag(m, -1), sag0);  // the default level is level 0
  EXPECT_GT(sag0, 0.01);
  EXPECT_LT(sag1, 0.8 * sag0);
  EXPECT_LT(sag2, 0.9 * sag1);
  // A scope without a section ignores the level: bit-identical to level 0 of the same EI.
  const ScopeModel plain = buildScopeModel(ScopeParams(), Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -9.81));
  EXPECT_EQ(tipSag(plain, 2), tipSag(plain, -1));
  EXPECT_EQ(tipSag(plain, -1), sag0);
}

TEST(VariableStiffness, TheLevelIsInTheSnapshot) {
  const ScopeModel m = sectionScope();
  ScopeState s = makeScopeState(m);
  HandleInput in;
  in.stiffness_level = 2;
  in.insertion_m = 0.001;
  stepScope(m, s, in, kDt);
  const std::vector<double> snap = getScopeState(s);
  EXPECT_EQ(snap.back(), 2.0);
  ScopeState t = makeScopeState(m);
  setScopeState(snap, t);
  EXPECT_EQ(t.input.stiffness_level, 2);
  EXPECT_EQ(getScopeState(ScopeState(makeScopeState(buildScopeModel(ScopeParams(), Vec3::Zero(), Vec3(1, 0, 0),
                                                                     Vec3(0, 0, 1), Vec3::Zero()))))
                .size(),
            snap.size() - 1);
}

}  // namespace
}  // namespace colosim
