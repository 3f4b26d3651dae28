#include "trainer/interactive.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>

#include <fcntl.h>
#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include "core/scope_kinematics.h"
#include "trainer/handle_io.h"
#include "trainer/replay.h"

namespace colosim {

HandleLimits handleLimitsOf(const ScopeModel& scope) {
  HandleLimits l;
  // The deepest insertion the scope model takes (clampHandleInput): one segment stays out.
  l.insertion_max_m = (scope.segment_count - 1) * scope.h_m;
  l.rotation_max_rad = kRotationMax_rad;
  return l;
}

namespace {

double finiteOr0(double x) { return std::isfinite(x) ? x : 0.0; }

// Moves x towards 0 by at most step (>= 0), without overshooting.
double towardsZero(double x, double step) { return x > 0 ? std::max(0.0, x - step) : std::min(0.0, x + step); }

}  // namespace

HandleInput integrateHandle(const HandleInput& prev, const HandleRates& rates, double dt_s,
                            const HandleLimits& limits) {
  HandleInput in;
  in.insertion_m =
      std::clamp(prev.insertion_m + dt_s * finiteOr0(rates.insertion_m_per_s), 0.0, limits.insertion_max_m);
  in.rotation_rad = std::clamp(prev.rotation_rad + dt_s * finiteOr0(rates.rotation_rad_per_s),
                               -limits.rotation_max_rad, limits.rotation_max_rad);
  if (rates.centre_knobs) {
    const double step_rad = dt_s * std::abs(finiteOr0(rates.knob_return_rad_per_s));
    in.knob_updown_rad = towardsZero(prev.knob_updown_rad, step_rad);
    in.knob_leftright_rad = towardsZero(prev.knob_leftright_rad, step_rad);
  } else {
    in.knob_updown_rad = prev.knob_updown_rad + dt_s * finiteOr0(rates.knob_updown_rad_per_s);
    in.knob_leftright_rad = prev.knob_leftright_rad + dt_s * finiteOr0(rates.knob_leftright_rad_per_s);
  }
  in.knob_updown_rad = std::clamp(in.knob_updown_rad, -limits.knob_updown_max_rad, limits.knob_updown_max_rad);
  in.knob_leftright_rad =
      std::clamp(in.knob_leftright_rad, -limits.knob_leftright_max_rad, limits.knob_leftright_max_rad);
  // Held: a press of the stiffness key changes it (nextStiffnessLevel).
  in.stiffness_level = rates.stiffness_level >= 0 ? rates.stiffness_level : prev.stiffness_level;
  return in;
}

int nextStiffnessLevel(const ScopeModel& scope, int current_level) {
  const int n = static_cast<int>(scope.params.variable_stiffness.levels.size());
  if (n == 0) return -1;
  HandleInput in;
  in.stiffness_level = current_level;
  return (stiffnessLevelOf(scope, in) + 1) % n;
}

namespace {

// A stick deflection beyond the dead zone, rescaled to [-1, 1].
double stick(double axis, double dead_zone) {
  const double a = std::clamp(finiteOr0(axis), -1.0, 1.0);
  const double mag = std::abs(a);
  if (mag <= dead_zone || dead_zone >= 1.0) return 0.0;
  return std::copysign((mag - dead_zone) / (1.0 - dead_zone), a);
}

// Keys (+1 / -1 / 0) plus stick, saturated at full scale.
double combine(bool plus, bool minus, double axis, double dead_zone) {
  const double keys = (plus ? 1.0 : 0.0) - (minus ? 1.0 : 0.0);
  return std::clamp(keys + stick(axis, dead_zone), -1.0, 1.0);
}

}  // namespace

HandleRates ratesFromControls(const ControlState& c, const ControlSpeeds& s) {
  const double k = c.fast ? s.fast_factor : 1.0;
  HandleRates r;
  r.insertion_m_per_s = k * s.insertion_m_per_s * combine(c.push, c.pull, c.axis_insertion, s.dead_zone);
  r.rotation_rad_per_s = k * s.rotation_rad_per_s * combine(c.rotate_cw, c.rotate_ccw, c.axis_rotation, s.dead_zone);
  r.knob_updown_rad_per_s = k * s.knob_rad_per_s * combine(c.tip_up, c.tip_down, c.axis_updown, s.dead_zone);
  r.knob_leftright_rad_per_s =
      k * s.knob_rad_per_s * combine(c.tip_right, c.tip_left, c.axis_leftright, s.dead_zone);
  r.centre_knobs = c.centre_knobs;
  r.knob_return_rad_per_s = k * s.knob_rad_per_s;
  return r;
}

InputSource operatorSource(const Scenario& scenario, double dt_s, const HandleLimits& limits,
                           const SharedRates& rates, bool autopilot) {
  const std::vector<Keyframe> script = scenario.script;
  // Steps of scripted set-up: those starting before until_s.
  const long setup_steps =
      scenario.start.kind == "scripted" ? static_cast<long>(std::ceil(scenario.start.until_s / dt_s - 1e-9)) : 0;
  return [script, dt_s, setup_steps, limits, &rates, autopilot](long step, const HandleInput& prev) {
    // The input of step k is the script at the step's start time k dt (as runScenario).
    if (autopilot || step < setup_steps) return scriptedInput(script, static_cast<double>(step) * dt_s);
    return integrateHandle(prev, rates.get(), dt_s, limits);
  };
}

void takeSnapshot(const Simulation& sim, long steps, Snapshot& out) {
  out.steps = steps;
  out.telemetry = sim.telemetry();
  out.has_scene = sim.scene(out.scene);
}

PhysicsLoop::PhysicsLoop(Simulation& sim, const ScoreOptions& scoring, SessionWriter* writer, InputSource source,
                         const PhysicsLoopOptions& options, std::function<void(const std::string&)> on_warning)
    : sim_(sim),
      scorer_(scoring),
      writer_(writer),
      source_(std::move(source)),
      options_(options),
      on_warning_(std::move(on_warning)),
      dt_s_(sim.dt_s()) {
  // The start input is what the simulation holds before any step.
  input_ = sim_.telemetry().input;
  if (!(dt_s_ > 0) || !source_) throw std::invalid_argument("PhysicsLoop: needs dt_s > 0 and an input source");
}

PhysicsLoop::~PhysicsLoop() { stop(); }

void PhysicsLoop::start() {
  if (thread_.joinable()) throw std::logic_error("PhysicsLoop::start: already started");
  running_ = true;
  thread_ = std::thread([this] {
    try {
      run();
    } catch (...) {
      error_ = std::current_exception();
      running_ = false;
    }
  });
  // Named for top and perf: the draw side shows as colosim and llvmpipe-N.
  pthread_setname_np(thread_.native_handle(), "physics");
}

void PhysicsLoop::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void PhysicsLoop::publish() {
  takeSnapshot(sim_, steps_, back_);
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  std::swap(back_, shared_);
  published_ = true;
}

bool PhysicsLoop::latest(Snapshot& out) {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  if (!published_ || out.steps == shared_.steps) return false;
  out = shared_;
  return true;
}

namespace {

// Step durations in 10 us bins up to 100 ms (the last bin holds everything longer): a
// median without keeping an hour of samples.
constexpr double kBin_s = 1e-5;
constexpr int kBins = 10000;

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

}  // namespace

void PhysicsLoop::run() {
  using Clock = std::chrono::steady_clock;
  running_ = true;
  std::vector<long> histogram(kBins, 0);
  double busy_s = 0.0, max_step_s = 0.0;
  const std::chrono::duration<double> dt(dt_s_);
  publish();  // the start state, for the first frame
  const double cpu_start_s = threadCpuSeconds();
  const Clock::time_point t_start = Clock::now();
  Clock::time_point origin = t_start;  // step origin_step is due at origin
  long origin_step = 0;
  while (!stop_ && (options_.max_steps < 0 || steps_ < options_.max_steps)) {
    // Pause: record the change at this step boundary, then idle without stepping.
    if (pause_requested_ != paused_) {
      paused_ = pause_requested_.load();
      if (writer_) writer_->event(steps_, paused_ ? "paused" : "resumed");
      if (paused_) {
        ++stats_.pauses;
      } else {
        origin = Clock::now();  // pacing starts again from here: no catching up on the pause
        origin_step = steps_;
      }
    }
    if (paused_) {
      const Clock::time_point idle_start = Clock::now();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      stats_.paused_s += std::chrono::duration<double>(Clock::now() - idle_start).count();
      continue;
    }
    if (options_.real_time) {
      const Clock::time_point due = origin + std::chrono::duration_cast<Clock::duration>(dt * (steps_ - origin_step));
      const Clock::time_point now = Clock::now();
      if (now < due) {
        std::this_thread::sleep_until(due);
      } else {
        // Late: run the steps back to back to catch up, unless too far behind.
        const long lag = static_cast<long>(std::chrono::duration<double>(now - due) / dt);
        stats_.max_lag_steps = std::max(stats_.max_lag_steps, lag);
        if (lag > options_.max_catch_up_steps) {
          stats_.dropped_steps += lag;
          ++stats_.drop_episodes;
          origin = now;
          origin_step = steps_;
          if (stats_.drop_episodes == 1 && on_warning_) {
            char msg[300];
            std::snprintf(msg, sizeof msg,
                          "physics fell %ld steps (%.0f ms) behind real time at step %ld; the lost time is "
                          "dropped (simulated time now runs late against the clock); further drops are "
                          "counted in the summary",
                          lag, 1e3 * lag * dt_s_, steps_);
            on_warning_(msg);
          }
        }
      }
    }
    const Clock::time_point t0 = Clock::now();
    {
      AssistInput asked;
      {
        std::lock_guard<std::mutex> lock(assist_mutex_);
        asked = assist_requested_;
      }
      if (asked != assist_) {
        sim_.assist(asked);
        if (writer_) writer_->assist(steps_, asked);
        assist_ = asked;
      }
    }
    const HandleInput in = source_(steps_, input_);
    stepAndRecord(sim_, in, steps_, scorer_, writer_);
    input_ = in;
    ++steps_;
    publish();
    const double step_s = std::chrono::duration<double>(Clock::now() - t0).count();
    busy_s += step_s;
    max_step_s = std::max(max_step_s, step_s);
    ++histogram[std::min(kBins - 1, static_cast<int>(step_s / kBin_s))];
  }
  const double wall_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  stats_.steps = steps_;
  stats_.cpu_s = threadCpuSeconds() - cpu_start_s;
  stats_.wall_s = wall_s;
  const double stepping_s = wall_s - stats_.paused_s;  // wall time not paused [s]
  stats_.steps_per_s = stepping_s > 0 ? steps_ / stepping_s : 0.0;
  stats_.busy_fraction = stepping_s > 0 ? busy_s / stepping_s : 0.0;
  stats_.step_ms_max = 1e3 * max_step_s;
  long seen = 0;
  for (int b = 0; b < kBins && steps_ > 0; ++b) {
    seen += histogram[b];
    if (2 * seen >= steps_) {
      stats_.step_ms_median = 1e3 * (b + 0.5) * kBin_s;
      break;
    }
  }
  running_ = false;
}

PhysicsLoopResult PhysicsLoop::finish(const std::string& ended_by) {
  if (thread_.joinable()) stop();
  if (finished_) throw std::logic_error("PhysicsLoop::finish: called twice");
  finished_ = true;
  if (error_) std::rethrow_exception(error_);
  PhysicsLoopResult r;
  r.steps = steps_;
  r.final_state_hash = sim_.stateHash();
  r.scores = scorer_.json();
  r.stats = stats_;
  if (writer_) {
    nlohmann::json summary{{"scores", r.scores},
                           {"interactive",
                            {{"wall_s", stats_.wall_s},
                             {"steps_per_s", stats_.steps_per_s},
                             {"dropped_steps", stats_.dropped_steps},
                             {"paused_s", stats_.paused_s},
                             {"pauses", stats_.pauses}}}};
    if (!ended_by.empty()) summary["interactive"]["ended_by"] = ended_by;
    writer_->end(steps_, r.final_state_hash, summary);
  }
  return r;
}

std::string newSessionPath(const std::string& dir, const std::string& scenario_name,
                           std::chrono::system_clock::time_point when) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir))
    throw std::runtime_error(dir + ": cannot create the sessions folder" + (ec ? ": " + ec.message() : ""));
  const std::time_t t = std::chrono::system_clock::to_time_t(when);
  std::tm local{};
  localtime_r(&t, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  // Only safe characters from the scenario's name.
  std::string name;
  for (char c : scenario_name) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  if (name.empty()) name = "session";
  for (int n = 1; n < 10000; ++n) {
    const std::string path = (fs::path(dir) / (std::string(stamp) + "_" + name +
                                               (n == 1 ? "" : "-" + std::to_string(n)) + ".jsonl"))
                                 .string();
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      ::close(fd);
      return path;
    }
    if (errno != EEXIST) throw std::runtime_error(path + ": cannot create the session file: " + std::strerror(errno));
  }
  throw std::runtime_error(dir + ": no free session file name for " + stamp);
}

}  // namespace colosim
