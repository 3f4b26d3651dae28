#include "trainer/world_simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <tuple>
#include <utility>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "core/colon_step.h"
#include "core/input_error.h"
#include "core/lumen_check.h"
#include "core/numbers.h"
#include "core/scope_step.h"
#include "trainer/assets.h"
#include "trainer/colon_simulation.h"
#include "trainer/json_position.h"
#include "trainer/scenario.h"
#include "trainer/start_state.h"

namespace colosim {

namespace {

// Onboard optics for the view measures: half of the ~140 deg diagonal field of view,
// and how far the tip light shows the wall usefully (the scores' "within 5 cm").
constexpr double kHalfFieldOfView_rad = 70.0 * kPi / 180.0;
constexpr double kViewDistance_m = 0.05;
constexpr double kRedoutDistance_m = 0.004;  // the lens closer than this to the wall: red-out
constexpr double kLumenLookahead_m = 0.04;   // the lumen ahead: the centreline 4 cm further on

// The colon location nearest x, searched around a tracked segment (+-3 segments).
ClosestPoint nearestAround(const Points& q, int tracked, const Vec3& x) {
  const int nseg = static_cast<int>(q.cols()) - 1;
  ClosestPoint best;
  best.distance = -1;
  const int lo = tracked < 0 ? 0 : std::max(0, tracked - 3);
  const int hi = tracked < 0 ? nseg - 1 : std::min(nseg - 1, tracked + 3);
  for (int j = lo; j <= hi; ++j) {
    const ClosestPoint c = closestPointOnSegment(q, j, x);
    if (best.distance < 0 || c.distance < best.distance) best = c;
  }
  return best;
}

}  // namespace

WorldSimulation::WorldSimulation(const Scenario& scenario, std::shared_ptr<const TensionLaw> law,
                                 const std::string& query_mode)
    : WorldSimulation(scenario, scenarioParameters(scenario), std::move(law), query_mode) {}

WorldSimulation::WorldSimulation(const Scenario& scenario, const Parameters& params,
                                 std::shared_ptr<const TensionLaw> law, const std::string& query_mode)
    : WorldSimulation(loadWorldModel(scenario.anatomy_path, params, std::move(law)), startSpecOf(scenario),
                      query_mode) {}

WorldSimulation::WorldSimulation(WorldModel model, const StartSpec& start, const std::string& query_mode)
    : model_(std::move(model)) {
  query_ = makeContactQuery(model_, query_mode);
  restart(start);
  // The assistant's hand: where the scenario's pressure presses, else the mobile loops.
  for (const PressureSchedule& p : pressure_) {
    bool seen = false;
    for (const PressureSchedule& a : assist_regions_)
      seen = seen || (a.region.first_segment == p.region.first_segment && a.region.last_segment == p.region.last_segment);
    if (!seen) assist_regions_.push_back(p);
  }
  if (assist_regions_.empty()) {
    for (const char* region : {"sigmoid", "transverse"}) {
      PressureSchedule p;
      std::tie(p.region.first_segment, p.region.last_segment) = regionSegments(model_.colon, region);
      if (p.region.first_segment < 0) continue;
      p.region.stiffness_N_per_m2 = kAssistPressure_N_per_m2;
      p.region.damping_Ns_per_m2 = kAssistDamping_Ns_per_m2;
      assist_regions_.push_back(p);
    }
  }
  for (PressureSchedule& p : assist_regions_) p.ramp_s = 1.0, p.from_s = p.to_s = 0;
  // The patient's position: the one whose gravity the model has.
  gravity_norm_ = model_.colon.gravity_m_per_s2.norm();
  for (const std::string& pos : patientPositions())
    if ((gravityForPosition(pos, gravity_norm_) - model_.colon.gravity_m_per_s2).norm() <= 1e-9 * (1 + gravity_norm_))
      position_ = pos;
  start_position_ = position_;
  start_gravity_ = model_.colon.gravity_m_per_s2;
  telemetry_.patient_position = position_;  // restart() measured before it was known
}

void WorldSimulation::assist(const AssistInput& a) {
  const double t_s = state_.colon.time_s;
  if (a.abdominal_pressure != assist_.abdominal_pressure) {
    if (assist_pressure_.empty()) {  // the first pressing: the schedules join the scenario's
      for (const PressureSchedule& p : assist_regions_) {
        assist_pressure_.push_back(pressure_.size());
        pressure_.push_back(p);
        state_.support.push_back(p.region);
        state_.support.back().stiffness_N_per_m2 = state_.support.back().damping_Ns_per_m2 = 0;
      }
    }
    for (size_t i : assist_pressure_) {
      PressureSchedule& p = pressure_[i];
      const double f = pressureRamp(t_s, p.from_s, p.to_s, p.ramp_s);  // where the ramp is now
      if (a.abdominal_pressure) {
        // Pressing again: the ramp goes on from where it is; a hand that had let go
        // presses the region where it lies now.
        p.from_s = t_s - f * p.ramp_s;
        p.to_s = std::numeric_limits<double>::infinity();
        if (f == 0) state_.support[i].anchor_q.resize(3, 0);
      } else {
        p.to_s = t_s + f * p.ramp_s;  // letting go: down from where it is
      }
    }
  }
  if (a.patient_position != assist_.patient_position) {
    // Empty: back to the position the run started in.
    startTurn(a.patient_position.empty() ? start_position_ : a.patient_position);
  }
  assist_ = a;
}

void WorldSimulation::startTurn(const std::string& target) {
  const double t_s = state_.colon.time_s;
  Vec3 g_to;
  try {
    g_to = gravityForPosition(target, 1.0);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("patient_position: ") + e.what());
  }
  const Vec3& g = model_.colon.gravity_m_per_s2;
  const double from_rad = std::atan2(g.y(), g.x());
  double by_rad = std::remainder(std::atan2(g_to.y(), g_to.x()) - from_rad, 2 * kPi);
  // Half a turn either way: through the side whose middle has gravity more posterior
  // (lateral to lateral over the back), ties towards the patient's left (supine to prone
  // over the left side).
  if (std::abs(std::abs(by_rad) - kPi) < 1e-9) {
    auto preference = [](double angle_rad) { return std::sin(angle_rad) + 1e-6 * std::cos(angle_rad); };
    by_rad = preference(from_rad + kPi / 2) >= preference(from_rad - kPi / 2) ? kPi : -kPi;
  }
  turn_from_rad_ = from_rad;
  turn_by_rad_ = by_rad;
  turn_start_s_ = t_s;
  position_ = target;
}

void WorldSimulation::turnGravity(double t_s) {
  if (turn_start_s_ < 0) return;
  const double x = std::clamp((t_s - turn_start_s_) / kTurnDuration_s, 0.0, 1.0);
  const double eased = x * x * (3 - 2 * x);  // smoothstep: no jolt at either end
  const double a = turn_from_rad_ + eased * turn_by_rad_;
  const Vec3 g = Vec3(gravity_norm_ * std::cos(a), gravity_norm_ * std::sin(a), 0.0);
  model_.colon.gravity_m_per_s2 = g;
  model_.scope.gravity_m_per_s2 = g;
  if (x >= 1) turn_start_s_ = -1;
}

void WorldSimulation::restart(const StartSpec& start) {
  // No assistance yet: the hand off, the patient back in the starting position.
  assist_ = AssistInput();
  assist_pressure_.clear();
  turn_start_s_ = -1;
  if (gravity_norm_ > 0) {
    position_ = start_position_;
    model_.colon.gravity_m_per_s2 = model_.scope.gravity_m_per_s2 = start_gravity_;
  }
  dt_s_ = start.dt_s;
  turns_ = start.patient_turns;
  next_turn_ = 0;
  StartState s = makeStartState(model_, start, query_.get());
  state_ = std::move(s.state);
  pressure_ = std::move(s.pressure);
  sigmoid_first_ = sigmoid_last_ = -1;
  for (int j = 0; j + 1 < model_.colon.n; ++j) {
    if (model_.colon.region_names[model_.colon.segment_region[j]] != "sigmoid") continue;
    if (sigmoid_first_ < 0) sigmoid_first_ = j;
    sigmoid_last_ = j + 1;
  }
  loop_last_ = sigmoid_last_;
  writhe_step_ = -1;
  for (int j = 0; j + 1 < model_.colon.n; ++j)
    if (model_.colon.region_names[model_.colon.segment_region[j]] == "descending") loop_last_ = j + 1;
  measure();
}

void WorldSimulation::setSupport(double t_s) {
  for (size_t i = 0; i < pressure_.size(); ++i) {
    const PressureSchedule& p = pressure_[i];
    RegionSupport& r = state_.support[i];
    const double f = pressureRamp(t_s, p.from_s, p.to_s, p.ramp_s);
    // The hand holds the region where it lies when the pressing begins (its first step).
    if (f > 0 && r.anchor_q.cols() == 0) r.anchor_q = state_.colon.q;
    r.stiffness_N_per_m2 = f * p.region.stiffness_N_per_m2;
    r.damping_Ns_per_m2 = f * p.region.damping_Ns_per_m2;
  }
}

void WorldSimulation::useTwoLanes(bool on) {
  if (!on)
    lanes_.reset();
  else if (!lanes_)
    lanes_ = std::make_unique<StepLanes>();
}

void WorldSimulation::step(const HandleInput& in) {
  // The pressure in force over this step: the ramp at the step's start time.
  if (!pressure_.empty()) setSupport(state_.colon.time_s);
  // The scenario's turns of the patient: each from the first step starting at or after its
  // time (half a step's tolerance for the clock's rounding).
  while (next_turn_ < turns_.size() && turns_[next_turn_].at_s <= state_.colon.time_s + 0.5 * dt_s_)
    startTurn(turns_[next_turn_++].position);
  turnGravity(state_.colon.time_s);
  stepWorld(model_, state_, in, *query_, dt_s_, lanes_.get());
  measure();
  telemetry_.solver_limited = limitedCount(state_);
  updateLimitEvents();
}

void WorldSimulation::updateLimitEvents() {
  events_.clear();
  const WorldState& s = state_;
  if (!s.colon.solver_ok) events_.push_back({"solver_failed_colon", "the colon solve failed or gave non-finite values: its velocities were set to zero"});
  if (!s.scope.solver_ok) events_.push_back({"solver_failed_scope", "the scope solve failed or gave non-finite values: its velocities were set to zero"});
  char buf[768];
  if (telemetry_.solver_limited == 0) {
    if (limited_run_steps_ > 0) {
      std::snprintf(buf, sizeof buf,
                    "after %ld steps; largest asked: contact force %.4g N, scope %.4g m/s and "
                    "%.4g rad/s, colon %.4g m/s, handle force %.4g N and torque %.4g N m; grip slip %.4g m, %.4g rad",
                    limited_run_steps_, run_force_N_, run_scope_speed_, run_scope_spin_, run_colon_speed_,
                    run_handle_force_N_, run_handle_torque_Nm_, s.scope.grip_slip_m, s.scope.grip_slip_rad);
      events_.push_back({"solver_limited_end", buf});
    }
    limited_run_steps_ = 0;
    run_force_N_ = run_scope_speed_ = run_scope_spin_ = run_colon_speed_ = 0;
    run_handle_force_N_ = run_handle_torque_Nm_ = 0;
    return;
  }
  if (limited_run_steps_ == 0) {
    const ContactLimitReport& c = s.contact_limit;
    std::snprintf(buf, sizeof buf,
                  "contact forces limited %d (asked %.4g N, limit %.4g N), dropped non-finite %d; "
                  "scope segments slowed %d (asked %.4g m/s, %.4g rad/s; limits %.4g m/s, %.4g rad/s); colon points "
                  "slowed %d (asked %.4g m/s, limit %.4g m/s); failed solves: colon %d, scope %d; handle grip "
                  "slipped %d (asked %.4g N, limit %.4g N; asked %.4g N m, limit %.4g N m)",
                  c.limited, c.asked_N, model_.contact.max_point_force_N, c.non_finite, s.scope.limited_segments,
                  s.scope.asked_speed_m_per_s, s.scope.asked_spin_rad_per_s, model_.scope.params.max_speed_m_per_s,
                  model_.scope.params.max_spin_rad_per_s, s.colon.limited_points, s.colon.asked_speed_m_per_s,
                  model_.colon.max_speed_m_per_s, s.colon.solver_ok ? 0 : 1, s.scope.solver_ok ? 0 : 1,
                  s.scope.grip_limited ? 1 : 0, s.scope.asked_handle_force_N, model_.scope.params.max_handle_force_N,
                  s.scope.asked_handle_torque_Nm, model_.scope.params.max_handle_torque_Nm);
    std::string detail = buf;
    if (c.limited > 0) {
      using Kind = ContactLimitReport::Worst::Kind;
      const ContactLimitReport::Worst& w = c.worst;
      if (w.kind == Kind::kThreading)
        std::snprintf(buf, sizeof buf, "; most asked by a threading contact at control point %d", w.colon_segment);
      else
        std::snprintf(buf, sizeof buf, "; most asked by %s at colon segment %d, p %.3f",
                      w.kind == Kind::kTipFace ? "a tip face point" : "a slice's interaction point", w.colon_segment, w.p);
      detail += buf;
      std::snprintf(buf, sizeof buf, ": %.4g N, %.3g mm deep, closing at %.3g m/s", w.asked_N, 1000 * w.depth_m,
                    w.closing_m_per_s);
      detail += buf;
    }
    events_.push_back({"solver_limited", detail});
  }
  ++limited_run_steps_;
  run_force_N_ = std::max(run_force_N_, s.contact_limit.asked_N);
  run_scope_speed_ = std::max(run_scope_speed_, s.scope.asked_speed_m_per_s);
  run_scope_spin_ = std::max(run_scope_spin_, s.scope.asked_spin_rad_per_s);
  run_colon_speed_ = std::max(run_colon_speed_, s.colon.asked_speed_m_per_s);
  if (s.scope.grip_limited) {
    run_handle_force_N_ = std::max(run_handle_force_N_, std::abs(s.scope.asked_handle_force_N));
    run_handle_torque_Nm_ = std::max(run_handle_torque_Nm_, std::abs(s.scope.asked_handle_torque_Nm));
  }
}

std::vector<Vec3> WorldSimulation::scopeCentreline() const {
  const ScopeState& s = state_.scope;
  const double h = model_.scope.h_m;
  std::vector<Vec3> line;
  // A few centimetres outside the anus, then every simulated segment's proximal end, then the tip.
  const int base = s.inside;
  line.push_back(s.p_W[base] - 1.5 * h * s.R_WS[base].col(2));
  line.push_back(s.p_W[base] + 0.5 * h * s.R_WS[base].col(2));
  for (int k = s.inside - 1; k >= 0; --k) line.push_back(s.p_W[k] + 0.5 * h * s.R_WS[k].col(2));
  return line;
}

bool WorldSimulation::scene(SceneView& out) const {
  out.colon = &model_.colon;
  out.colon_q = state_.colon.q;
  out.scope_centreline_m = scopeCentreline();
  out.scope_radius_m = model_.scope.radius_m;
  out.tip_light_reach_m = model_.scope.params.tip_light_reach_m;
  out.p_WTip_m = tipPosition(model_.scope, state_.scope);
  out.R_WTip = state_.scope.R_WS[0];
  return true;
}

double WorldSimulation::coronalLoopTurns(const Vec3& tip) {
  const WorldState& s = state_;
  const int slices = model_.scope.params.slices_per_segment;
  std::vector<Vec3>& line = loop_line_;
  line.clear();
  line.push_back(model_.scope.p_W_anus);
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    const int j = s.slice_track[k * slices].colon_segment;
    if (j >= loop_last_) break;  // the scope has left the descending colon
    line.push_back(s.scope.p_W[k]);
  }
  if (line.size() == static_cast<size_t>(s.scope.inside) + 1) line.push_back(tip);
  return crossingLoopTurns(line, Vec3(0, -1, 0));
}

void WorldSimulation::measure() {
  const ColonModel& colon = model_.colon;
  const ScopeModel& scope = model_.scope;
  const WorldState& s = state_;
  Telemetry& t = telemetry_;
  region_ratio_.swap(t.region_length_ratio);  // keep the storage across the reset
  t = Telemetry();
  t.time_s = s.colon.time_s;
  t.input = s.scope.input;
  t.handle_force_N = s.scope.handle.force_N;
  t.handle_torque_Nm = s.scope.handle.torque_Nm;
  if (handle_and_loop_only_) {
    t.tip_position_m = tipPosition(scope, s.scope);
    if (s.scope.inside > 0) t.loop_turns = coronalLoopTurns(t.tip_position_m);
    return;
  }
  // Contact topology: is every slice tracked in the lumen it is really in?
  const LumenCheck lumen = checkLumen(model_, s, lumen_arc_);
  t.track_jump_m = lumen.track_jump_m;
  t.wall_penetration_m = lumen.wall_penetration_m;
  t.lumen_exit = lumen.lumen_exit;
  // Peak wall force: the largest force one scope segment (1.5 cm) puts on the wall.
  {
    double seg_force = 0, peak = 0, total = 0;
    int seg = -1;
    for (const WallContact& c : s.wall) {
      if (c.scope_segment != seg) seg = c.scope_segment, seg_force = 0;
      seg_force += c.force_N;
      total += c.force_N;
      peak = std::max(peak, seg_force);
    }
    t.wall_force_peak_N = peak;
    t.wall_force_total_N = total;  // the whole scope's load on the wall (design studies)
  }
  const Vec3 tip = tipPosition(scope, s.scope);
  t.tip_position_m = tip;
  t.tip_to_caecum_m = (tip - s.colon.q.col(colon.n - 1)).norm();
  if (resting_q_.cols() != colon.n || (turn_start_s_ < 0 && colon.gravity_m_per_s2 != resting_gravity_)) {
    resting_q_ = restingColon(colon);
    resting_gravity_ = colon.gravity_m_per_s2;
  }
  t.mesentery_stretch = mesenteryStretch(colon, s.colon, &resting_q_);
  t.abdominal_pressure = assist_.abdominal_pressure;
  t.patient_position = position_;
  t.patient_turning = turn_start_s_ >= 0;
  t.region_length_ratio.swap(region_ratio_);
  regionLengthRatios(colon, s.colon.q, t.region_length_ratio);
  t.colon_stretch = colonStretch(t.region_length_ratio);
  t.region_names = &colon.region_names;
  t.inserted_m = s.scope.inside > 0 ? s.scope.input.insertion_m - s.scope.grip_slip_m : 0.0;
  t.patch_count = (colon.n - 1) * kPatchSectors;
  if (s.scope.inside == 0) {
    t.lumen_visible = true;
    return;
  }

  // Loop measure: the scope from the anus to the end of the descending colon (by the
  // colon location each segment tracks), projected on the coronal plane (normal: the
  // antero-posterior axis, so that the sign reads as seen from the front): the turning
  // number of the loop it closes by crossing itself (crossingLoopTurns). An alpha loop's
  // return limb can cross the first limb where it enters the descending colon (the loop
  // drags the mobile sigmoid towards it), so the line does not stop at the sigmoid's end.
  // An earlier measure, net turning against the rest sigmoid's, called a straightened
  // sigmoid a half loop; a crossing is what an alpha loop looks like under fluoroscopy.
  {
    t.loop_turns = coronalLoopTurns(tip);
    const std::vector<Vec3>& line = loop_line_;
    // The same line in 3-D, closed far away: out of the anus against the entry direction,
    // and up (cranially, along the descending colon) from its far end.
    // Measured at the first step of each interval of kWritheEverySteps steps: the multiples
    // of it, or where a start or a restart (which forgets the last one) lands.
    const long step = std::lround(s.colon.time_s / dt_s_);
    if (writhe_step_ < 0 || step / kWritheEverySteps != writhe_step_ / kWritheEverySteps) {
      loop_writhe_ = writheClosedFarAway(line, -scope.R_W_entry.col(2), Vec3(0, 0, 1));
      writhe_step_ = step;
    }
    t.loop_writhe = loop_writhe_;
  }

  // The view from the tip: red-out, lumen ahead, wall patches seen.
  const Mat3& R = s.scope.R_WS[0];
  const Vec3 forward = R.col(2);
  const int tracked = s.slice_track.empty() ? -1 : s.slice_track[scope.params.slices_per_segment - 1].colon_segment;
  t.tip_against_wall = lensAgainstWall(colon, s.colon.q, tracked, tip, forward);
  const ClosestPoint here = nearestAround(s.colon.q, tracked, tip);
  const double s_here = colon.arclengthAt(here.segment, here.p);
  t.tip_arclength_m = s_here;
  // The centreline point kLumenLookahead_m further towards the caecum (rest arclength).
  const double s_target = std::min(s_here + kLumenLookahead_m, colon.length_m());
  int jt = here.segment;
  while (jt + 1 < colon.n - 1 && colon.s_rest_m(jt + 1) < s_target) ++jt;
  const double pt = std::clamp((s_target - colon.s_rest_m(jt)) / colon.segment_length_m(jt), 0.0, 1.0);
  const Vec3 to_lumen = splinePoint(s.colon.q, jt, pt) - tip;
  t.lumen_visible = !t.tip_against_wall && to_lumen.norm() > 1e-6 &&
                    std::acos(std::clamp(to_lumen.normalized().dot(forward), -1.0, 1.0)) < kHalfFieldOfView_rad;
  // Patches: kPatchSectors around each colon segment near the tip; seen when within 5 cm,
  // in the field of view (the tip light lights what the camera sees). Occlusion by folds
  // is not modelled.
  const int j0 = std::max(0, here.segment - 4), j1 = std::min(colon.n - 2, here.segment + 4);
  for (int j = j0; j <= j1; ++j) {
    const Vec3 c = splinePoint(s.colon.q, j, 0.5);
    const Vec3 tangent = splineTangent(s.colon.q, j, 0.5).normalized();
    Vec3 u = tangent.cross(Vec3::UnitZ());
    if (u.norm() < 1e-6) u = tangent.cross(Vec3::UnitX());
    u.normalize();
    const Vec3 w = tangent.cross(u);
    const double r = colon.radiusAt(j, 0.5);
    for (int a = 0; a < kPatchSectors; ++a) {
      const double ang = 2 * kPi * (a + 0.5) / kPatchSectors;
      const Vec3 patch = c + r * (std::cos(ang) * u + std::sin(ang) * w);
      const Vec3 d = patch - tip;
      const double dist = d.norm();
      if (dist > kViewDistance_m || dist < 1e-6) continue;
      if (std::acos(std::clamp(d.dot(forward) / dist, -1.0, 1.0)) > kHalfFieldOfView_rad) continue;
      t.patches_seen.push_back(j * kPatchSectors + a);
    }
  }
}

bool lensAgainstWall(const ColonModel& colon, const Points& q, int tracked, const Vec3& tip_W, const Vec3& forward_W) {
  const ClosestPoint ahead = nearestAround(q, tracked, tip_W + kRedoutDistance_m * forward_W);
  // The contact wall's folds (ColonParams::haustral_fold_depth) narrow it over a
  // control-point spacing either side of each fold, where the picture is not red.
  return ahead.distance > colon.smoothRadiusAt(ahead.segment, ahead.p);
}

std::unique_ptr<Simulation> makeWorldSimulation(const Scenario& scenario) {
  return std::make_unique<WorldSimulation>(scenario);
}

}  // namespace colosim
