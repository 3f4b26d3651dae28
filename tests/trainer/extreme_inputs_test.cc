// Extreme inputs (issue 8, docs/hardening.md): scripts that slam the handle controls
// (assets/scenarios/extreme/) run on the colon + scope + contacts simulation. Every step
// the whole state must be finite and the energy and speeds bounded by what the hand can
// put in; when a solver limit engages, the session records it and the run goes on.
#include <gtest/gtest.h>

#include <chrono>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "core/colon_step.h"
#include "core/scope_step.h"
#include "core/spline.h"
#include "fixture.h"
#include "trainer/clinical_manoeuvres.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/score.h"
#include "trainer/session.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

// Bounds on the state, each from what the hand can put in (docs/hardening.md):
// the handle moves at most ~1 m/s and 10 turns/s here, the scope weighs 0.32 kg, the
// colon ~0.8 kg. A scope moving bodily at 1 m/s holds 0.16 J; the bounds leave a factor
// of ~30 for whipping and elastic energy, and an exploding state passes them in a few steps.
constexpr double kMaxKinetic_J = 5.0;           // colon + scope kinetic energy [J]
constexpr double kMaxSpeed_m_per_s = 20.0;      // any colon control point or scope segment [m/s]
constexpr double kMaxSpin_rad_per_s = 500.0;    // any scope segment's angular speed [rad/s] (handle: 62.8)
constexpr double kMaxReach_m = 1.0;             // any body point from the anus [m] (the abdomen is ~0.4 m across)

struct Extremes {
  double kinetic_J = 0, colon_speed = 0, scope_speed = 0, scope_spin = 0, reach_m = 0;
  double wall_force_N = 0, handle_force_N = 0, handle_torque_Nm = 0;
  double grip_slip_m = 0;  ///< largest |commanded - actual insertion| [m]
  long first_bad_step = -1;  ///< first step with a non-finite or out-of-bound state
  std::string what;
};

bool finite3(const Vec3& v) { return std::isfinite(v(0)) && std::isfinite(v(1)) && std::isfinite(v(2)); }

// Checks the state after `step` steps and updates the extremes.
void check(const WorldSimulation& sim, long step, Extremes& x) {
  const WorldModel& m = sim.model();
  const WorldState& s = sim.state();
  const Vec3 anus = m.scope.p_W_anus;
  bool ok = s.colon.q.allFinite() && s.colon.v.allFinite();
  double colon_speed = 0, scope_speed = 0, spin = 0, reach = 0;
  for (int i = 0; i < m.colon.n; ++i) {
    colon_speed = std::max(colon_speed, s.colon.v.col(i).norm());
    reach = std::max(reach, (s.colon.q.col(i) - anus).norm());
  }
  for (int k = 0; k < s.scope.inside; ++k) {
    ok = ok && finite3(s.scope.p_W[k]) && finite3(s.scope.v_W[k]) && finite3(s.scope.w_W[k]) &&
         s.scope.R_WS[k].allFinite();
    scope_speed = std::max(scope_speed, s.scope.v_W[k].norm());
    spin = std::max(spin, s.scope.w_W[k].norm());
    reach = std::max(reach, (s.scope.p_W[k] - anus).norm());
  }
  const double kinetic = colonEnergy(m.colon, s.colon).kinetic_J + scopeKineticEnergy(m.scope, s.scope);
  ok = ok && std::isfinite(kinetic) && std::isfinite(s.scope.handle.force_N) && std::isfinite(s.scope.handle.torque_Nm);
  x.kinetic_J = std::max(x.kinetic_J, kinetic);
  x.grip_slip_m = std::max(x.grip_slip_m, std::abs(s.scope.grip_slip_m));
  x.colon_speed = std::max(x.colon_speed, colon_speed);
  x.scope_speed = std::max(x.scope_speed, scope_speed);
  x.scope_spin = std::max(x.scope_spin, spin);
  x.reach_m = std::max(x.reach_m, reach);
  x.wall_force_N = std::max(x.wall_force_N, s.max_wall_force_N);
  x.handle_force_N = std::max(x.handle_force_N, std::abs(s.scope.handle.force_N));
  x.handle_torque_Nm = std::max(x.handle_torque_Nm, std::abs(s.scope.handle.torque_Nm));
  if (x.first_bad_step >= 0) return;
  char buf[256];
  if (!ok) {
    x.first_bad_step = step;
    x.what = "non-finite state";
  } else if (kinetic > kMaxKinetic_J || colon_speed > kMaxSpeed_m_per_s || scope_speed > kMaxSpeed_m_per_s ||
             spin > kMaxSpin_rad_per_s || reach > kMaxReach_m) {
    x.first_bad_step = step;
    std::snprintf(buf, sizeof buf, "kinetic %.3g J, colon %.3g m/s, scope %.3g m/s, spin %.3g rad/s, reach %.3g m",
                  kinetic, colon_speed, scope_speed, spin, reach);
    x.what = buf;
  }
}

struct ExtremeRun {
  Extremes x;
  uint64_t hash = 0;
  long steps = 0;
  nlohmann::json scores;
  double wall_s = 0;
};

// Runs the scenario's script through the same stepAndRecord as colosim run, checking
// every step; records the session to `session_path` when given.
// With `params`, the run uses them instead of the scenario's file and overrides (no session
// then: the session names the scenario's parameter file).
ExtremeRun runScenario(const Scenario& sc, const std::string& name, const std::string& session_path = "",
                       const Parameters* params = nullptr) {
  WorldSimulation sim = params ? WorldSimulation(sc, *params) : WorldSimulation(sc);
  assert(session_path.empty() || !params);
  std::unique_ptr<SessionWriter> writer;
  if (!session_path.empty()) writer = std::make_unique<SessionWriter>(session_path, sessionHeaderFor(sc, "test"));
  Scorer scorer(sc.scoring);
  ExtremeRun r;
  const auto t0 = std::chrono::steady_clock::now();
  check(sim, 0, r.x);
  for (long k = 0; k < sc.steps(); ++k) {
    stepAndRecord(sim, scriptedInput(sc.script, k * sc.dt_s), k, scorer, writer.get());
    check(sim, k + 1, r.x);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = sc.steps();
  r.hash = sim.stateHash();
  r.scores = scorer.json();
  if (writer) writer->end(r.steps, r.hash, nlohmann::json{{"scores", r.scores}});
  std::printf("%s: %ld steps in %.2f s; kinetic max %.4g J, colon %.3g m/s, scope %.3g m/s, spin %.3g rad/s, "
              "reach %.3g m, wall force max %.3g N, handle force max %.4g N, torque max %.4g N m\n",
              name.c_str(), r.steps, r.wall_s, r.x.kinetic_J, r.x.colon_speed, r.x.scope_speed, r.x.scope_spin,
              r.x.reach_m, r.x.wall_force_N, r.x.handle_force_N, r.x.handle_torque_Nm);
  return r;
}

ExtremeRun runExtreme(const std::string& name, const std::string& session_path = "") {
  return runScenario(findScenario(test::asset("scenarios/extreme/" + name + ".json")), name, session_path);
}

// The grip's limits (ScopeParams, docs/hardening.md): the handle force and torque may pass
// them by at most 1 % (the grip aims at 99 % of them from an affine fit of the reaction;
// measured: never above 100.00 N).
constexpr double kGripMargin = 1.01;

void expectSurvived(const ExtremeRun& r) {
  EXPECT_EQ(r.x.first_bad_step, -1) << "at step " << r.x.first_bad_step << ": " << r.x.what;
  EXPECT_TRUE(std::isfinite(r.scores["peak_handle_force_N"].get<double>()));
  const ScopeParams grip;
  EXPECT_LE(r.x.handle_force_N, kGripMargin * grip.max_handle_force_N);
  EXPECT_LE(r.x.handle_torque_Nm, kGripMargin * grip.max_handle_torque_Nm);
}

// Issue 16 (core/lumen_check.h), at every step: no slice centre outside its lumen, tracks
// continuous along the scope, no interaction point 5 mm beyond its wall.
void expectInTheLumen(const ExtremeRun& r) {
  EXPECT_EQ(r.scores["lumen_exit_steps"].get<long>(), 0);
  EXPECT_LT(r.scores["max_track_jump_m"].get<double>(), 0.03);
  EXPECT_LT(r.scores["max_wall_penetration_m"].get<double>(), 0.005);
}

TEST(ExtremeInputs, PushAtOneMetrePerSecondIntoTheCaecum) {
  const ExtremeRun r = runExtreme("extreme_push");
  expectSurvived(r);
  expectInTheLumen(r);
}
TEST(ExtremeInputs, SpinTenTurnsPerSecond) {
  const ExtremeRun r = runExtreme("extreme_spin");
  expectSurvived(r);
  expectInTheLumen(r);
}
// The wires give way (ScopeParams::knob_moment_limit_Nm) and the lens guard holds the lens.
TEST(ExtremeInputs, KnobsSwungAndSlammedEndToEnd) {
  const ExtremeRun r = runExtreme("extreme_knobs");
  expectSurvived(r);
  expectInTheLumen(r);
}

// The withdrawal of everything at once gathers the free sigmoid onto the spinning scope
// (1.7 m of colon per m of scope). Variants of its script (docs/hardening.md): with the
// wall sampled at the scope's slices only (threading_stiffness 0, the paper's wall) the
// gathered colon buckles sideways between two slices and the scope runs through the neck
// of the loop it leaves, out of the rectum into the sigmoid beside it: a track jump of a
// third of a metre. The threading contacts (core/colon_threading.h) hold every control
// point between two slices around the scope, and each variant stays in the lumen.
// Session 27 allowed one step per run: a slice's interaction point closing on the wall at
// 3.8 m/s, 3.7 mm in, asked 29 N of the 20 N point limit in the shipped script, and 4 of 9
// runs (the shipped script and eight variants) met the limiter once. Since session 28 the
// threading stop (core/colon_threading.h) holds the control points that closed on the scope
// faster than a step allows. Since session 43 (the retroperitoneal colon held firmer, the
// contacts' coupling predictor) the withdrawal can snap the coil the push gathered: the
// distal 20-30 cm slide back at 4-5 m/s together and the tip asks up to 5.8 m/s of the
// scope's 5 m/s speed limit, which trims it (6 and 2 steps in the variants 0.9/0.8 and
// 0.9/1.0). The runs must not stand on that limit: with it lifted to 8 m/s every run meets
// no limit at all and stays in the lumen as deep as with it (docs/clinical-mechanics.md,
// session 43). The shipped script meets no limit either way.
TEST(ExtremeInputs, VariantsOfEverythingAtOnceStayInTheLumen) {
  const ExtremeRun shipped = runExtreme("extreme_all");
  expectSurvived(shipped);
  expectInTheLumen(shipped);
  EXPECT_EQ(shipped.scores["solver_limited_steps"].get<long>(), 0);
  for (const auto& [time_scale, knob_scale] : {std::pair{0.9, 0.8}, std::pair{1.1, 0.8}, std::pair{0.9, 1.0}}) {
    SCOPED_TRACE("time x " + std::to_string(time_scale) + ", knobs x " + std::to_string(knob_scale));
    const Scenario sc = everythingAtOnce(time_scale, knob_scale);
    const ExtremeRun r = runScenario(sc, "extreme_all variant");
    expectSurvived(r);
    expectInTheLumen(r);
    Parameters lifted = scenarioParameters(sc);
    lifted.scope.max_speed_m_per_s = 8.0;
    const ExtremeRun free = runScenario(sc, "extreme_all variant, the scope's speed limit at 8 m/s", "", &lifted);
    expectSurvived(free);
    expectInTheLumen(free);
    EXPECT_EQ(free.scores["solver_limited_steps"].get<long>(), 0) << "beyond trimming the snap, no limit engages";
  }
}

TEST(ExtremeInputs, WithoutThreadingAVariantOfEverythingAtOnceTunnels) {
  test::TempDir dir;
  nlohmann::json params = nlohmann::json::parse(test::readFile(test::asset("params/default.json")));
  params["contact"]["threading_stiffness"]["value"] = 0.0;
  const std::string path = dir.file("no_threading.json");
  std::ofstream(path) << params.dump();
  Scenario sc = everythingAtOnce(1.1, 0.8);  // (0.9, 0.8) until session 43; on the firmer patient it stays in
  useParameterFile(sc, path);
  const ExtremeRun r = runScenario(sc, "extreme_all variant, no threading");
  expectSurvived(r);
  EXPECT_GT(r.scores["lumen_exit_steps"].get<long>(), 50);
  EXPECT_GT(r.scores["max_track_jump_m"].get<double>(), 0.2);
}

// The lens guard's reaction (core/world.cc): in a step where the guard stopped the lens
// (the knob slams press the face on the wall), the colon was stepped with the opposite
// impulse at the lens's track: its last load is the guard's impulse over the step, along
// the wall's outward normal, where the tip slice is tracked. Action equals reaction.
TEST(ExtremeInputs, TheLensGuardsReactionLoadsTheWall) {
  const Scenario sc = findScenario(test::asset("scenarios/extreme/extreme_knobs.json"));
  WorldSimulation sim(sc);
  long engaged = 0;
  for (long k = 0; k < sc.steps() && engaged < 5; ++k) {
    sim.step(scriptedInput(sc.script, k * sc.dt_s));
    const WorldState& s = sim.state();
    const double impulse = s.scope.lens_impulse_Ns;
    if (!(impulse > 0)) continue;
    ++engaged;
    ASSERT_FALSE(s.colon.loads.empty());
    const SplineLoad& l = s.colon.loads.back();
    EXPECT_EQ(l.segment, s.lens_wall_segment);
    EXPECT_EQ(l.p, s.lens_wall_p);
    EXPECT_LT((l.force_N - (impulse / sc.dt_s) * s.scope.lens_wall.n_W).norm(), 1e-12 * l.force_N.norm());
    EXPECT_TRUE(l.stiffness_N_per_m.isZero());
  }
  EXPECT_EQ(engaged, 5) << "the slams never pressed the lens on the wall: the test tests nothing";
}

// The lens guard stops the lens at where its wall will be at the end of the step, not where
// the wall's velocity at the start would take it: in everything-at-once, the colon dragged
// by the push decelerates within the step (its wall 0.3-1.1 m/s slower than at the start),
// and with the start's velocity the lens ended up to 0.57 mm beyond the guard's line, 0.07 mm
// outside the lumen (core/world.cc, lensMayReachWall). Now, in every step where the guard
// held the lens, the lens ends inside the lumen of the wall it was held at.
TEST(ExtremeInputs, TheLensGuardHoldsTheLensInsideTheWallItWillMeet) {
  const Scenario sc = findScenario(test::asset("scenarios/extreme/extreme_all.json"));
  WorldSimulation sim(sc);
  const WorldModel& m = sim.model();
  long engaged = 0;
  double worst_beyond_line_m = -1;
  for (long k = 0; k < sc.steps(); ++k) {
    sim.step(scriptedInput(sc.script, k * sc.dt_s));
    const WorldState& s = sim.state();
    if (!(s.scope.lens_impulse_Ns > 0)) continue;
    ++engaged;
    const Vec3 lens = tipFacePoint(m.scope, s.scope, 0);
    const double radius_m = m.colon.radiusAt(s.lens_wall_segment, s.lens_wall_p);
    const double beyond_line_m = (lens - splinePoint(s.colon.q, s.lens_wall_segment, s.lens_wall_p)).norm() -
                                 (radius_m - m.contact.lens_margin_m);
    worst_beyond_line_m = std::max(worst_beyond_line_m, beyond_line_m);
  }
  EXPECT_GT(engaged, 100) << "the guard hardly engaged: the test tests little";
  EXPECT_LT(worst_beyond_line_m, m.contact.lens_margin_m) << "the lens left the lumen in a step the guard held it";
}

// The recorded session of run r replays to the same state hashes, final hash and count of
// limited steps.
void expectReplaysBitIdentically(const ReplayPlan& plan, const ExtremeRun& r, long limited_steps) {
  WorldSimulation again(plan.scenario);
  const ReplayResult rr = replay(plan, again);
  EXPECT_TRUE(rr.hashOk()) << rr.mismatch;
  EXPECT_TRUE(rr.final_hash_checked);
  EXPECT_EQ(rr.final_state_hash, r.hash);
  EXPECT_EQ(rr.scores["solver_limited_steps"], limited_steps);
}

// Everything at once pushed and pulled at 2 m/s (its script 0.5 times as long) asks for
// more than the solves are trusted with: the limiter engages, the session says so in event
// lines, the scores count it, the state stays finite, and the recording replays
// bit-identically. (The knob slams alone did until the wires gave way,
// ScopeParams::knob_moment_limit_Nm; the shipped everything at once did until the colon was
// held round the scope between slices, core/colon_threading.h; at 1.25 m/s it did, 8 steps
// from 1.935 s, until the point limit went from 20 to 60 N in session 29; at 1.67 m/s it did,
// a wall point asking 66.6 N at 0.904 s, until the patient of session 43, whose firmer
// fixation keeps the coil out of that corner.) Measured: 10 steps in which the scope's
// segments ask up to 5.8 m/s of the 5 m/s speed limit, the deepest point 4.7 mm. The run is
// cut at 1.0 s for its cost under the sanitizers (scripts/sanitize).
TEST(ExtremeInputs, LimiterEngagesIsRecordedAndReplays) {
  test::TempDir dir;
  const std::string path = dir.file("all.jsonl");
  Scenario sc = everythingAtOnce(0.5, 1.0);
  sc.duration_s = 1.0;
  const ExtremeRun r = runScenario(sc, "extreme_all at 2 m/s, its first 1.0 s", path);
  expectSurvived(r);
  // In the lumen, but a point whose force the limiter held lies beyond the 4.84 mm at
  // which the wall and its backing give the 60 N limit (measured: 5.4 mm at the deepest),
  // so the depth is bounded by 6 mm here, not by the 5 mm of runs the limiter leaves alone.
  EXPECT_EQ(r.scores["lumen_exit_steps"].get<long>(), 0);
  EXPECT_LT(r.scores["max_track_jump_m"].get<double>(), 0.03);
  EXPECT_LT(r.scores["max_wall_penetration_m"].get<double>(), 0.006);
  const long limited_steps = r.scores["solver_limited_steps"].get<long>();
  const long episodes = r.scores["solver_limited_episodes"].get<long>();
  EXPECT_GT(limited_steps, 0);
  EXPECT_GT(episodes, 0);
  EXPECT_LE(episodes, limited_steps);

  const ReplayPlan plan = planReplay(path);
  int starts = 0, ends = 0;
  for (const SessionEvent& e : plan.session.events) {
    if (e.name == "solver_limited") {
      ++starts;
      EXPECT_NE(e.detail.find("limit 60 N"), std::string::npos) << e.detail;
      EXPECT_NE(e.detail.find("250 rad/s"), std::string::npos) << e.detail;
    } else if (e.name == "solver_limited_end") {
      ++ends;
      EXPECT_NE(e.detail.find("after "), std::string::npos) << e.detail;
    } else {
      ADD_FAILURE() << "unexpected event " << e.name << ": " << e.detail;
    }
  }
  EXPECT_EQ(starts, episodes) << "one solver_limited event per run of limited steps";
  EXPECT_GE(ends, starts - 1);
  EXPECT_LE(ends, starts);
  expectReplaysBitIdentically(plan, r, limited_steps);
}

// Everything at once at 2.5 m/s (its script 0.4 times as long): where the command turns
// from push to pull (0.92 s) the scope's segments ask 5-7 m/s of the 5 m/s speed limit, a
// move is no longer answered affinely, and the grip's search cannot hold the reaction
// within the grip. It must at least not end beyond what the hand's own move asked: before
// the search kept the least of its moves, it took a step asking 143.5 N to -849.5 N (and
// the run's peak pull to 1403 N; since, 544 N: still beyond the grip, docs/hardening.md).
TEST(ExtremeInputs, TheGripNeverEndsFurtherBeyondItsLimitThanTheHandsMoveAsked) {
  Scenario sc = everythingAtOnce(0.4, 1.0);
  WorldSimulation sim(sc);
  const ScopeParams grip;
  auto excess = [&](double force_N, double torque_Nm) {
    return std::max(std::abs(force_N) / grip.max_handle_force_N, std::abs(torque_Nm) / grip.max_handle_torque_Nm);
  };
  int slipped = 0;
  for (long k = 0; k < std::lround(0.95 / sim.dt_s()); ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    const ScopeState& s = sim.state().scope;
    if (!s.grip_limited) continue;
    ++slipped;
    EXPECT_LE(excess(s.handle.force_N, s.handle.torque_Nm),
              excess(s.asked_handle_force_N, s.asked_handle_torque_Nm) + 1e-9)
        << "step " << k << ": asked " << s.asked_handle_force_N << " N, ended at " << s.handle.force_N << " N";
  }
  EXPECT_GT(slipped, 0) << "the grip never slipped: the test tests nothing";
}

// Pushed at 1 m/s against sticky walls the handle force reaches the grip's limit: the grip
// slips (the actual insertion differs from the command), the force stays within 1 % of the
// limit at every step, the session's solver_limited events name the handle force asked
// against the limit, the scores count the steps, and the recording replays bit-identically.
// (With the 20 N point limit, until session 29, a wall point reached it a few steps before
// the grip slipped, so the run of limited steps began with the contact; at 60 N each event
// is a slip, asking 100.1-106.9 N.)
TEST(ExtremeInputs, JammedAgainstStickyWallsTheGripSlipsIsRecordedAndReplays) {
  test::TempDir dir;
  const std::string path = dir.file("jam.jsonl");
  const ExtremeRun r = runExtreme("extreme_jam", path);
  expectSurvived(r);
  expectInTheLumen(r);  // the wall bottoms out (ContactParams::wall_thickness_m)
  const ScopeParams grip;
  EXPECT_GT(r.x.handle_force_N, 0.95 * grip.max_handle_force_N) << "the grip was never reached: the test tests nothing";
  const long limited_steps = r.scores["solver_limited_steps"].get<long>();
  EXPECT_GT(limited_steps, 0);

  const ReplayPlan plan = planReplay(path);
  EXPECT_GT(r.x.grip_slip_m, 0.01) << "the grip never slipped";
  int grip_events = 0;
  for (const SessionEvent& e : plan.session.events) {
    if (e.name != "solver_limited") continue;
    const size_t at = e.detail.find("handle grip slipped ");
    ASSERT_NE(at, std::string::npos) << e.detail;
    double asked_N = 0;
    ASSERT_EQ(std::sscanf(e.detail.c_str() + at, "handle grip slipped %*d (asked %lf N", &asked_N), 1) << e.detail;
    EXPECT_NE(e.detail.find("limit 100 N;"), std::string::npos) << e.detail;
    grip_events += asked_N > 0.9 * grip.max_handle_force_N;
  }
  EXPECT_GT(grip_events, 0);
  expectReplaysBitIdentically(plan, r, limited_steps);
}

// The contacts' coupling (ContactParams::coupling_predictor) on the firmer patient of
// session 43: with the predictor, as shipped, everything at once at 1.67 m/s (its first
// second) stays in the lumen; with the lag (each body feels the other's move a step late, as
// before session 43) the scope leaves it (measured: 112 exit steps, 5.4 mm deep, the
// limiter in 34 steps). Before the predictor was shipped this test checked the reverse
// worry, that the predictor (unlimited, it once curled the slammed bending section into a
// ring and left the lumen for 81 steps) keeps this run and the jam in: docs/numerics.md,
// "The predictor's stability".
TEST(ExtremeInputs, WithTheLagAVariantOfEverythingAtOnceLeavesTheLumen) {
  Scenario all = everythingAtOnce(0.6, 1.0);
  all.duration_s = 1.0;
  Parameters p = scenarioParameters(all);
  ASSERT_TRUE(p.contact.coupling_predictor);
  const ExtremeRun predicted = runScenario(all, all.name + " with the coupling predictor", "", &p);
  expectSurvived(predicted);
  expectInTheLumen(predicted);
  p.contact.coupling_predictor = false;
  const ExtremeRun lagged = runScenario(all, all.name + " with the contacts' lag", "", &p);
  expectSurvived(lagged);
  EXPECT_GT(lagged.scores["lumen_exit_steps"].get<long>(), 20);
}

// A clinical-pace insertion never reaches a limit: the first 16 s of free_insertion (the
// rectum and the rectosigmoid junction, steering with both knobs). (sigmoid_push and
// sigmoid_untwist start from a threaded alpha loop whose bent scope springs back in the
// first steps; that release is limited for 2 steps and recorded, which is what the
// limiter is for.)
TEST(ExtremeInputs, ClinicalPaceNeverEngagesTheLimiter) {
  Scenario sc = findScenario("free_insertion");
  WorldSimulation sim(sc);
  long limited = 0;
  for (long k = 0; k < 16000; ++k) {
    sim.step(scriptedInput(sc.script, k * sc.dt_s));
    limited += sim.telemetry().solver_limited;
  }
  EXPECT_EQ(limited, 0);
}

}  // namespace
}  // namespace colosim
