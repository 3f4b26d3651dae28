// What happened when in a session: the telemetry a report plots against time and the
// events it marks, recorded from the same per-step Telemetry the Scorer reads and with
// the Scorer's rules, so that the marks agree with the scores (trainer/score.h).
#pragma once

#include <vector>

#include "trainer/score.h"
#include "trainer/telemetry.h"

namespace colosim {

/// One point of a timeline: over a bin of time, the value of largest magnitude of each
/// quantity (sign kept), so that the plotted peaks are the scored peaks.
struct TimelineSample {
  double time_s = 0;             ///< end of the bin [s]
  double handle_force_N = 0;     ///< + push [N]
  double handle_torque_Nm = 0;   ///< [N m]
  double wall_force_N = 0;       ///< largest scope-wall contact force [N]
  double loop_turns = 0;         ///< [turns]
  double mesentery_stretch = 0;  ///< lifter load over the colon's weight [-]
  double colon_stretch = 0;      ///< discomfort source: present / rest length - 1, largest region [-]
  double tip_arclength_m = 0;    ///< tip depth along the colon from the anus [m]
};

struct TimeInterval {
  double from_s = 0, to_s = 0;  ///< [s]
};

struct SessionTimeline {
  double start_s = 0;  ///< scoring starts here [s]; before it, the set-up (no events marked)
  std::vector<TimelineSample> samples;
  /// Excessive-pressure episodes: the wall force above ScoreOptions::excessive_wall_force_N
  /// for longer than episode_min_s (one per scored episode, from the first step above).
  std::vector<TimeInterval> pressure_episodes;
  std::vector<TimeInterval> redout;   ///< the tip against the wall
  std::vector<double> lumen_lost_s;   ///< the lumen leaves the onboard view [s]
};

/// Consumes one Telemetry record per step (as Scorer::add) and builds the timeline.
class TimelineRecorder {
 public:
  /// `bin_s`: the timeline's resolution [s] (default 50 ms: 72,000 samples an hour).
  explicit TimelineRecorder(const ScoreOptions& options, double bin_s = 0.05);
  void add(const Telemetry& t);
  /// The timeline so far (intervals still open end at the last record).
  SessionTimeline timeline() const;

 private:
  ScoreOptions o_;
  double bin_s_;
  SessionTimeline tl_;
  long bin_ = -1;
  double last_time_s_;
  double episode_from_s_ = -1;  ///< start of the current above-threshold run; < 0: none
  double episode_s_ = 0;        ///< its length [s]
  bool episode_counted_ = false;
  double redout_from_s_ = -1;   ///< start of the current red-out; < 0: none
  bool lumen_was_visible_ = true;
};

}  // namespace colosim
