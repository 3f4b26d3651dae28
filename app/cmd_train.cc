// colosim train [SCENARIO]: the interactive trainer (trainer/train_window.h): its options,
// then the exit summary.
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "app/options.h"
#include "trainer/strict_json.h"
#include "trainer/train_window.h"

namespace colosim::app {

namespace {

struct TrainOptions {
  std::string scenario;  // empty: the start screen, free_insertion preselected
  std::string size = "1280x480";
  bool json = false;
  TrainWindowOptions window;
};

int runTrain(TrainOptions o) {
  // Every input is read and checked before a window or a file is opened.
  if (o.scenario.empty()) o.window.start_screen = true;
  const Scenario scenario = findScenario(o.scenario.empty() ? "free_insertion" : o.scenario);
  const SizePx size = parseSize(o.size, 64);
  o.window.width_px = size.width, o.window.height_px = size.height;
  o.window.colosim_version = COLOSIM_VERSION;
  const TrainWindowResult r = runTrainWindow(scenario, o.window);
  const PhysicsLoopStats& stats = r.loop.stats;
  const double physics_cpu_pct = stats.wall_s > 0 ? 100.0 * stats.cpu_s / stats.wall_s : 0.0;
  const char* lp = std::getenv("LP_NUM_THREADS");
  auto orNull = [](const std::string& v) { return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(v); };
  if (o.json) {
    nlohmann::json j{{"scenario", orNull(r.scenario)},
                     {"session", orNull(r.session_path)},
                     {"sessions", r.sessions},
                     {"screens", r.screens},
                     {"patient_position", orNull(r.patient_position)},
                     {"ended_by", orNull(r.ended_by)},
                     {"steps", r.loop.steps},
                     {"simulated_s", r.loop.steps * r.dt_s},
                     {"wall_s", stats.wall_s},
                     {"paused_s", stats.paused_s},
                     {"physics_steps_per_s", stats.steps_per_s},
                     {"dropped_steps", stats.dropped_steps},
                     {"physics_busy_pct", 100.0 * stats.busy_fraction},
                     {"physics_cpu_pct", physics_cpu_pct},
                     {"step_ms_median", stats.step_ms_median},
                     {"step_ms_max", stats.step_ms_max},
                     {"frames", r.frames},
                     {"frames_per_s", r.frames_per_s},
                     {"frame_ms_median", r.frame_ms_median},
                     {"draw_cpu_ms_per_frame", r.draw_cpu_ms_per_frame},
                     {"load_average_1min", r.load_average_1min},
                     {"render_scale", o.window.render_scale},
                     {"window_px", std::to_string(r.framebuffer_width_px) + "x" +
                                       std::to_string(r.framebuffer_height_px)},
                     {"view", r.view},
                     {"lp_num_threads", lp ? nlohmann::json(lp) : nlohmann::json(nullptr)},
                     {"final_state_hash", r.sessions.empty() ? nlohmann::json(nullptr)
                                                             : nlohmann::json(hashToHex(r.loop.final_state_hash))},
                     {"scores", r.loop.scores},
                     {"score_card", r.score_card}};
    std::cout << j.dump() << "\n";
    return 0;
  }
  if (r.sessions.empty()) {
    std::printf("colosim train: no session was started\n");
    return 0;
  }
  std::printf("colosim train %s (%s): %ld steps (%.3f s simulated) in %.2f s of wall time (%.2f s paused), "
              "ended by %s\n",
              r.scenario.c_str(), r.patient_position.c_str(), r.loop.steps, r.loop.steps * r.dt_s, stats.wall_s,
              stats.paused_s, r.ended_by.c_str());
  std::printf("  physics              %.1f steps/s (target %.0f), %ld steps dropped, CPU %.0f %% of a core, "
              "step median %.2f ms, max %.2f ms\n",
              stats.steps_per_s, 1.0 / r.dt_s, stats.dropped_steps, physics_cpu_pct, stats.step_ms_median,
              stats.step_ms_max);
  std::printf("  drawing              %.1f frames/s (%ld frames, median %.1f ms, CPU %.1f ms a frame, %dx%d, %s view%s%s)\n",
              r.frames_per_s, r.frames, r.frame_ms_median, r.draw_cpu_ms_per_frame, r.framebuffer_width_px,
              r.framebuffer_height_px, r.view.c_str(), lp ? ", LP_NUM_THREADS=" : "", lp ? lp : "");
  std::printf("  load average         %.2f (1 min, at the start; the machine's other work competes)\n",
              r.load_average_1min);
  std::printf("  final state hash     %s\n", hashToHex(r.loop.final_state_hash).c_str());
  std::printf("  session recorded in  %s\n", r.session_path.c_str());
  for (size_t k = 0; k + 1 < r.sessions.size(); ++k)
    std::printf("  earlier session      %s\n", r.sessions[k].c_str());
  printScores(r.loop.scores);
  return 0;
}

}  // namespace

void addTrainCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<TrainOptions>();
  TrainWindowOptions& w = o->window;
  CLI::App* cmd = app.add_subcommand("train", "Interactive trainer: drive the scope in a window, recorded")
                      ->footer(kTrainKeyHelp);
  cmd->add_option("SCENARIO", o->scenario,
                  "scenario file, or the name of one in assets/scenarios/; without it the start screen "
                  "(free_insertion preselected)");
  cmd->add_flag("--start-screen", w.start_screen,
                "open on the start screen even with SCENARIO (preselected there)");
  cmd->add_option("--record", w.record, "record the session into this new file (never overwritten)");
  cmd->add_option("--record-dir", w.record_dir,
                  "otherwise record into a new file YYYYMMDD-HHMMSS_SCENARIO.jsonl in this folder")
      ->capture_default_str();
  cmd->add_option("--view", w.view, "view at the start (keys 1, 2, 3 switch)")
      ->check(CLI::IsMember({"onboard", "global", "both"}))
      ->capture_default_str();
  cmd->add_option("--size", o->size, "window size WxH [px]")->capture_default_str();
  cmd->add_option("--quit-after", w.quit_after_s, "end the session this many wall seconds after the first frame (tests, demos)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_flag("--autopilot", w.autopilot, "the handle follows the scenario's script instead of the controls");
  cmd->add_option("--render-threads", w.render_threads,
                  "rasteriser threads of Mesa's llvmpipe (sets LP_NUM_THREADS; 0: Mesa's default, one per "
                  "core); default: cores - 1, so that physics keeps a core, unless LP_NUM_THREADS is set")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--render-scale", w.render_scale,
                  "draw the onboard view at this fraction of its size and stretch it (its fragment work "
                  "goes with the square; 1: full size)")
      ->check(CLI::Range(0.25, 1.0))
      ->capture_default_str();
  cmd->add_option("--screenshot", w.screenshot, "write the last frame into this new PNG file");
  cmd->add_flag("--json", o->json, "print one JSON object on stdout at the end (rates, session, scores)");
  cmd->callback([&action, o] { action = [o]() -> int { return runTrain(*o); }; });
}

}  // namespace colosim::app
