#include "trainer/start_state.h"

#include <memory>

#include "collision/contact_query.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>

#include "core/colon_step.h"
#include "core/input_error.h"
#include "core/scope_step.h"

namespace colosim {

std::pair<int, int> regionSegments(const ColonModel& colon, const std::string& region) {
  int first = -1, last = -1;
  for (int j = 0; j + 1 < colon.n; ++j) {
    if (colon.region_names[colon.segment_region[j]] != region) continue;
    if (first < 0) first = j;
    last = j;
  }
  return {first, last};
}

namespace {

// The start state's colon shape (ScenarioStart::shape_region): the region's control points
// placed along the uniform Catmull-Rom curve through `waypoints` (ends extrapolated),
// at their rest arclength spacing scaled to the curve's length; velocities zero.
void placeColonRegion(const ColonModel& colon, ColonState& s, const std::string& region,
                      const std::vector<Vec3>& waypoints, const std::string& where) {
  // The control points bounding the region's segments.
  const auto [first, last_segment] = regionSegments(colon, region);
  const int last = last_segment + 1;
  if (first < 0) throw InputError(where + ": start.colon_shape.region: no region '" + region + "' in the anatomy");
  const Vec3 p_first = s.q.col(first), p_last = s.q.col(last);
  if ((waypoints.front() - p_first).norm() > 0.01 || (waypoints.back() - p_last).norm() > 0.01) {
    char msg[256];
    std::snprintf(msg, sizeof msg, "must start within 1 cm of (%.4f, %.4f, %.4f) and end within 1 cm of (%.4f, %.4f, %.4f) m",
                  p_first.x(), p_first.y(), p_first.z(), p_last.x(), p_last.y(), p_last.z());
    throw InputError(where + ": start.colon_shape.points_m: " + msg + " (the " + region + "'s ends)");
  }
  // The curve, densely sampled (Catmull-Rom through the waypoints, 64 samples a span).
  const int m = static_cast<int>(waypoints.size());
  Points w(3, m + 2);
  for (int i = 0; i < m; ++i) w.col(i + 1) = waypoints[i];
  w.col(0) = 2 * waypoints[0] - waypoints[1];
  w.col(m + 1) = 2 * waypoints[m - 1] - waypoints[m - 2];
  std::vector<Vec3> curve;
  for (int seg = 1; seg < m; ++seg)
    for (int k = 0; k < 64; ++k) curve.push_back(splinePoint(w, seg, k / 64.0));
  curve.push_back(waypoints.back());
  std::vector<double> arc(curve.size(), 0.0);
  for (size_t i = 1; i < curve.size(); ++i) arc[i] = arc[i - 1] + (curve[i] - curve[i - 1]).norm();
  const double rest_span = colon.s_rest_m(last) - colon.s_rest_m(first);
  size_t i = 0;
  for (int j = first; j <= last; ++j) {
    const double target = arc.back() * (colon.s_rest_m(j) - colon.s_rest_m(first)) / rest_span;
    while (i + 2 < curve.size() && arc[i + 1] < target) ++i;
    const double f = std::clamp((target - arc[i]) / std::max(arc[i + 1] - arc[i], 1e-12), 0.0, 1.0);
    s.q.col(j) = (1 - f) * curve[i] + f * curve[i + 1];
    s.v.col(j).setZero();
  }
}

}  // namespace

StartSpec startSpecOf(const Scenario& scenario) {
  StartSpec spec;
  spec.dt_s = scenario.dt_s;
  if (scenario.start.kind == "settled") spec.settle_s = scenario.start.settle_s;
  spec.shape_region = scenario.start.shape_region;
  spec.shape_points_m = scenario.start.shape_points_m;
  spec.abdominal_pressure = scenario.abdominal_pressure;
  spec.patient_turns = scenario.patient_turns;
  if (!scenario.script.empty()) spec.first_input = scenario.script.front().input;
  spec.file = scenario.file;
  return spec;
}

StartState makeStartState(const WorldModel& model, const StartSpec& spec, ContactQuery* query,
                          const SettleObserver& observe) {
  // An error found here names the line of its key in the scenario file.
  auto fail = [&spec](const std::string& message) {
    return spec.file.empty() ? InputError(message) : scenarioError(spec.file, message);
  };
  StartState out;
  WorldState& s = out.state;
  s = makeWorldState(model);
  // Settle: the colon under gravity with the scope out; the clock starts afterwards.
  if (spec.settle_s > 0) {
    const long steps = std::lround(spec.settle_s / spec.dt_s);
    for (long k = 0; k < steps; ++k) {
      stepColon(model.colon, s.colon, spec.dt_s);
      if (observe && !observe(k + 1, s.colon)) break;
    }
    out.settled_clock_s = s.colon.time_s;
    s.colon.time_s = 0.0;
  }
  // Colon shape: one region displaced from its rest shape, at rest.
  if (!spec.shape_region.empty()) {
    try {
      placeColonRegion(model.colon, s.colon, spec.shape_region, spec.shape_points_m, spec.file);
    } catch (const InputError& e) {
      throw fail(e.what());
    }
  }
  // Abdominal pressure: each named region's spline segments, switched off until its time.
  for (size_t i = 0; i < spec.abdominal_pressure.size(); ++i) {
    const AbdominalPressure& a = spec.abdominal_pressure[i];
    PressureSchedule p;
    p.from_s = a.from_s, p.to_s = a.to_s, p.ramp_s = a.ramp_s;
    p.region.stiffness_N_per_m2 = a.stiffness_N_per_m2;
    p.region.damping_Ns_per_m2 = a.damping_Ns_per_m2;
    std::tie(p.region.first_segment, p.region.last_segment) = regionSegments(model.colon, a.region);
    if (p.region.first_segment < 0)
      throw fail(spec.file + ": abdominal_pressure[" + std::to_string(i) + "].region: no region '" + a.region +
                 "' in the anatomy");
    out.pressure.push_back(p);
    s.support.push_back(p.region);
    s.support.back().stiffness_N_per_m2 = s.support.back().damping_Ns_per_m2 = 0;
  }
  // Threading: a start with the scope already in is placed along the colon (pushing it in
  // within one step would be a 1 kHz jump).
  const HandleInput& first = spec.first_input;
  if (first.insertion_m > 0) threadScopeAlongColon(model, s, first.insertion_m, first.rotation_rad);
  s.scope.input = clampHandleInput(model.scope, first);
  // Relaxation: the threaded scope is bent along the centreline with no wall holding it;
  // it comes to rest against the wall with the handle held, then the clock starts.
  if (first.insertion_m > 0 && spec.relax_s > 0) {
    std::unique_ptr<ContactQuery> own;
    if (!query) query = (own = makeContactQuery(model, "fcl")).get();
    const HandleInput held = s.scope.input;
    const long steps = std::lround(spec.relax_s / spec.dt_s);
    for (long k = 0; k < steps; ++k) stepWorld(model, s, held, *query, spec.dt_s);
    s.colon.time_s = 0.0;
  }
  return out;
}

}  // namespace colosim
