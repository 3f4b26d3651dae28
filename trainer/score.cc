#include "trainer/score.h"

#include <algorithm>
#include <cmath>

namespace colosim {

namespace {
// Durations are sums of step lengths: 500 steps of 1 ms may add up to a hair over
// 0.5 s. Comparisons of durations with thresholds allow this much [s].
constexpr double kTimeTolerance_s = 1e-9;

nlohmann::json pct(double part_s, double whole_s) {
  return whole_s > 0 ? 100.0 * part_s / whole_s : 0.0;
}
}  // namespace

void PhaseScore::add(const Telemetry& t, double dt_s, const Telemetry* prev) {
  duration_s += dt_s;
  // Handle forces.
  const double f = t.handle_force_N, tq = std::abs(t.handle_torque_Nm);
  peak_handle_force_N = std::max(peak_handle_force_N, std::abs(f));
  peak_push_N = std::max(peak_push_N, f);
  peak_pull_N = std::max(peak_pull_N, -f);
  peak_handle_torque_Nm = std::max(peak_handle_torque_Nm, tq);
  handle_force_integral_Ns += std::abs(f) * dt_s;
  handle_torque_integral_Nms += tq * dt_s;
  if (std::abs(f) > o_.high_handle_force_N) high_force_time_s += dt_s;
  // Wall pressure: an episode is a run above the threshold lasting longer than
  // episode_min_s, counted once when it gets that long.
  peak_wall_force_N = std::max(peak_wall_force_N, t.wall_force_peak_N);
  peak_wall_force_total_N = std::max(peak_wall_force_total_N, t.wall_force_total_N);
  wall_force_integral_Ns += t.wall_force_total_N * dt_s;
  if (t.wall_force_peak_N > o_.excessive_wall_force_N) {
    excessive_pressure_time_s += dt_s;
    episode_s_ += dt_s;
    if (!episode_counted_ && episode_s_ > o_.episode_min_s + kTimeTolerance_s) {
      ++excessive_pressure_episodes;
      episode_counted_ = true;
    }
  } else {
    episode_s_ = 0;
    episode_counted_ = false;
  }
  // Discomfort from the colon's stretch; the mesentery's load beside it.
  peak_colon_stretch = std::max(peak_colon_stretch, t.colon_stretch);
  if (t.colon_stretch > o_.discomfort_strain) {
    discomfort_index_s += (t.colon_stretch - o_.discomfort_strain) * dt_s;
    discomfort_time_s += dt_s;
  }
  peak_mesentery_stretch = std::max(peak_mesentery_stretch, t.mesentery_stretch);
  if (t.mesentery_stretch > o_.discomfort_stretch) mesentery_stretch_time_s += dt_s;
  // Loops.
  max_loop_turns = std::max(max_loop_turns, std::abs(t.loop_turns));
  if (std::abs(t.loop_turns) >= o_.loop_turns) loop_time_s += dt_s;
  loop_writhe_max = std::max(loop_writhe_max, std::abs(t.loop_writhe));
  // Pleating: the shortest each region gets.
  if (t.region_names && t.region_names->size() == t.region_length_ratio.size()) {
    for (size_t r = 0; r < t.region_length_ratio.size(); ++r) {
      const auto [it, added] = region_length_ratio_min.emplace((*t.region_names)[r], t.region_length_ratio[r]);
      if (!added) it->second = std::min(it->second, t.region_length_ratio[r]);
    }
  }
  // View.
  if (t.tip_against_wall) redout_time_s += dt_s;
  if (t.lumen_visible) lumen_visible_time_s += dt_s;
  if (lumen_was_visible_ && !t.lumen_visible) ++lumen_lost_count;
  lumen_was_visible_ = t.lumen_visible;
  // Paths.
  if (prev) {
    tip_path_m += (t.tip_position_m - prev->tip_position_m).norm();
    insertion_path_m += std::abs(t.input.insertion_m - prev->input.insertion_m);
    const double pushed_m = t.inserted_m - prev->inserted_m;
    if (pushed_m > 0)
      shaft_movement_without_tip_progress_m +=
          std::max(0.0, pushed_m - std::max(0.0, t.tip_arclength_m - prev->tip_arclength_m));
    rotation_path_rad += std::abs(t.input.rotation_rad - prev->input.rotation_rad);
    knob_path_rad += std::abs(t.input.knob_updown_rad - prev->input.knob_updown_rad) +
                     std::abs(t.input.knob_leftright_rad - prev->input.knob_leftright_rad);
  }
  // Mucosa: cumulative time each patch was seen (a patch listed twice counts once).
  patch_count = std::max(patch_count, t.patch_count);
  std::vector<int> ids = t.patches_seen;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (int id : ids)
    if (id >= 0 && id < t.patch_count) patch_seen_s[id] += dt_s;
}

nlohmann::json PhaseScore::json() const {
  nlohmann::json j;
  j["duration_s"] = duration_s;
  j["peak_handle_force_N"] = peak_handle_force_N;
  j["peak_push_N"] = peak_push_N;
  j["peak_pull_N"] = peak_pull_N;
  j["peak_handle_torque_Nm"] = peak_handle_torque_Nm;
  j["handle_force_integral_Ns"] = handle_force_integral_Ns;
  j["handle_torque_integral_Nms"] = handle_torque_integral_Nms;
  j["high_force_time_pct"] = pct(high_force_time_s, duration_s);
  j["peak_wall_force_N"] = peak_wall_force_N;
  j["peak_wall_force_total_N"] = peak_wall_force_total_N;
  j["wall_force_integral_Ns"] = wall_force_integral_Ns;
  j["shaft_movement_without_tip_progress_m"] = shaft_movement_without_tip_progress_m;
  j["excessive_pressure_episodes"] = excessive_pressure_episodes;
  j["excessive_pressure_time_s"] = excessive_pressure_time_s;
  j["discomfort_index"] = discomfort_index_s;
  j["discomfort_time_pct"] = pct(discomfort_time_s, duration_s);
  j["peak_colon_stretch"] = peak_colon_stretch;
  j["peak_mesentery_stretch"] = peak_mesentery_stretch;
  j["mesentery_stretch_time_pct"] = pct(mesentery_stretch_time_s, duration_s);
  j["loop_time_s"] = loop_time_s;
  j["max_loop_turns"] = max_loop_turns;
  j["loop_writhe_max"] = loop_writhe_max;
  nlohmann::json ratios = nlohmann::json::object();
  for (const auto& [name, ratio] : region_length_ratio_min) ratios[name] = ratio;
  j["region_length_ratio_min"] = ratios;
  if (patch_count > 0) {
    int seen = 0;
    for (const auto& [id, s] : patch_seen_s)
      if (s >= o_.patch_seen_min_s - kTimeTolerance_s) ++seen;
    j["mucosa_visualised_pct"] = 100.0 * seen / patch_count;
  } else {
    j["mucosa_visualised_pct"] = nullptr;  // not measured by this simulation
  }
  j["redout_time_s"] = redout_time_s;
  j["lumen_lost_count"] = lumen_lost_count;
  j["lumen_visible_pct"] = pct(lumen_visible_time_s, duration_s);
  j["tip_path_m"] = tip_path_m;
  j["insertion_path_m"] = insertion_path_m;
  j["rotation_path_rad"] = rotation_path_rad;
  j["knob_path_rad"] = knob_path_rad;
  j["tip_path_per_insertion_path"] =
      insertion_path_m > 0 ? nlohmann::json(tip_path_m / insertion_path_m) : nlohmann::json(nullptr);
  return j;
}

Scorer::Scorer(const ScoreOptions& options)
    : o_(options), total_(options), insertion_(options), withdrawal_(options), last_time_s_(options.start_s) {}

void Scorer::add(const Telemetry& t) {
  if (t.solver_limited > 0) {
    ++limited_steps_;
    if (!was_limited_) ++limited_episodes_;
  }
  was_limited_ = t.solver_limited > 0;
  max_track_jump_m_ = std::max(max_track_jump_m_, t.track_jump_m);
  max_wall_penetration_m_ = std::max(max_wall_penetration_m_, t.wall_penetration_m);
  if (t.lumen_exit) ++lumen_exit_steps_;
  if (t.time_s <= o_.start_s) {  // set-up, not scored; still the reference for paths
    prev_ = t;
    have_prev_ = true;
    return;
  }
  const double dt_s = t.time_s - last_time_s_;
  last_time_s_ = t.time_s;
  const Telemetry* prev = have_prev_ ? &prev_ : nullptr;
  total_.add(t, dt_s, prev);
  if (!time_to_caecum_s_) {
    insertion_.add(t, dt_s, prev);
    if (t.tip_to_caecum_m <= o_.caecum_reach_m) {
      time_to_caecum_s_ = t.time_s - o_.start_s;
      insertion_at_caecum_m_ = t.inserted_m;
    }
  } else {
    withdrawal_.add(t, dt_s, prev);
  }
  prev_ = t;
  have_prev_ = true;
}

nlohmann::json Scorer::json() const {
  nlohmann::json j = total_.json();
  j["time_to_caecum_s"] = time_to_caecum_s_ ? nlohmann::json(*time_to_caecum_s_) : nlohmann::json(nullptr);
  j["insertion_at_caecum_m"] =
      insertion_at_caecum_m_ ? nlohmann::json(*insertion_at_caecum_m_) : nlohmann::json(nullptr);
  j["insertion"] = insertion_.json();
  j["withdrawal"] = time_to_caecum_s_ ? withdrawal_.json() : nlohmann::json(nullptr);
  j["solver_limited_steps"] = limited_steps_;
  j["solver_limited_episodes"] = limited_episodes_;
  j["max_track_jump_m"] = max_track_jump_m_;
  j["max_wall_penetration_m"] = max_wall_penetration_m_;
  j["lumen_exit_steps"] = lumen_exit_steps_;
  j["thresholds"] = {{"caecum_reach_m", o_.caecum_reach_m},
                     {"excessive_wall_force_N", o_.excessive_wall_force_N},
                     {"episode_min_s", o_.episode_min_s},
                     {"discomfort_strain", o_.discomfort_strain},
                     {"discomfort_stretch", o_.discomfort_stretch},
                     {"loop_turns", o_.loop_turns},
                     {"patch_seen_min_s", o_.patch_seen_min_s},
                     {"high_handle_force_N", o_.high_handle_force_N},
                     {"start_s", o_.start_s}};
  nlohmann::json units;
  for (const auto& [k, u] : Scorer::units()) units[k] = u;
  j["units"] = units;
  return j;
}

const std::map<std::string, std::string>& Scorer::units() {
  static const std::map<std::string, std::string> u = {
      {"duration_s", "s"}, {"time_to_caecum_s", "s"},
      {"peak_handle_force_N", "N"}, {"peak_push_N", "N"}, {"peak_pull_N", "N"},
      {"peak_handle_torque_Nm", "N m"}, {"handle_force_integral_Ns", "N s"},
      {"handle_torque_integral_Nms", "N m s"}, {"high_force_time_pct", "%"},
      {"peak_wall_force_N", "N (one scope segment)"}, {"peak_wall_force_total_N", "N (whole scope)"},
      {"wall_force_integral_Ns", "N s"}, {"shaft_movement_without_tip_progress_m", "m"},
      {"excessive_pressure_episodes", "1"},
      {"excessive_pressure_time_s", "s"},
      {"discomfort_index", "s (time integral of the colon's stretch above the threshold)"},
      {"discomfort_time_pct", "%"}, {"peak_colon_stretch", "- (present / rest length - 1, largest region)"},
      {"peak_mesentery_stretch", "- (lifter load beyond the resting colon's / colon weight)"}, {"mesentery_stretch_time_pct", "%"},
      {"loop_time_s", "s"}, {"max_loop_turns", "turns"},
      {"loop_writhe_max", "turns (writhe)"}, {"region_length_ratio_min", "- (present / rest length)"},
      {"insertion_at_caecum_m", "m"}, {"mucosa_visualised_pct", "%"},
      {"redout_time_s", "s"}, {"lumen_lost_count", "1"}, {"lumen_visible_pct", "%"},
      {"tip_path_m", "m"}, {"insertion_path_m", "m"}, {"rotation_path_rad", "rad"},
      {"knob_path_rad", "rad"}, {"tip_path_per_insertion_path", "m/m"},
      {"solver_limited_steps", "1"}, {"solver_limited_episodes", "1"},
      {"max_track_jump_m", "m"}, {"max_wall_penetration_m", "m"}, {"lumen_exit_steps", "1"}};
  return u;
}

}  // namespace colosim
