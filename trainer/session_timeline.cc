#include "trainer/session_timeline.h"

#include <cmath>

namespace colosim {

namespace {
// As in score.cc: durations are sums of steps and may exceed a threshold by rounding [s].
constexpr double kTimeTolerance_s = 1e-9;

void keepLargest(double& kept, double v) {
  if (std::abs(v) > std::abs(kept)) kept = v;
}
}  // namespace

TimelineRecorder::TimelineRecorder(const ScoreOptions& options, double bin_s)
    : o_(options), bin_s_(bin_s), last_time_s_(options.start_s) {
  tl_.start_s = options.start_s;
}

void TimelineRecorder::add(const Telemetry& t) {
  // The plotted quantities, over the whole session (the set-up too).
  const long bin = static_cast<long>(std::ceil(t.time_s / bin_s_ - 1e-9));
  if (bin != bin_) {
    bin_ = bin;
    TimelineSample s;
    s.time_s = t.time_s;
    tl_.samples.push_back(s);
  }
  TimelineSample& s = tl_.samples.back();
  s.time_s = t.time_s;
  keepLargest(s.handle_force_N, t.handle_force_N);
  keepLargest(s.handle_torque_Nm, t.handle_torque_Nm);
  keepLargest(s.wall_force_N, t.wall_force_peak_N);
  keepLargest(s.loop_turns, t.loop_turns);
  keepLargest(s.mesentery_stretch, t.mesentery_stretch);
  keepLargest(s.colon_stretch, t.colon_stretch);
  keepLargest(s.tip_arclength_m, t.tip_arclength_m);

  // Events, in scored time only, by the Scorer's rules (PhaseScore::add).
  if (t.time_s <= o_.start_s) return;
  const double step_from_s = last_time_s_;
  last_time_s_ = t.time_s;
  if (t.wall_force_peak_N > o_.excessive_wall_force_N) {
    if (episode_from_s_ < 0) episode_from_s_ = step_from_s, episode_s_ = 0;
    episode_s_ += t.time_s - step_from_s;  // summed as the Scorer sums it
    if (!episode_counted_ && episode_s_ > o_.episode_min_s + kTimeTolerance_s) {
      tl_.pressure_episodes.push_back({episode_from_s_, t.time_s});
      episode_counted_ = true;
    }
    if (episode_counted_) tl_.pressure_episodes.back().to_s = t.time_s;
  } else {
    episode_from_s_ = -1;
    episode_counted_ = false;
  }
  if (t.tip_against_wall) {
    if (redout_from_s_ < 0) {
      redout_from_s_ = step_from_s;
      tl_.redout.push_back({step_from_s, t.time_s});
    }
    tl_.redout.back().to_s = t.time_s;
  } else {
    redout_from_s_ = -1;
  }
  if (lumen_was_visible_ && !t.lumen_visible) tl_.lumen_lost_s.push_back(t.time_s);
  lumen_was_visible_ = t.lumen_visible;
}

SessionTimeline TimelineRecorder::timeline() const { return tl_; }

}  // namespace colosim
