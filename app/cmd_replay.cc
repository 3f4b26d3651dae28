// colosim replay SESSION [--frames DIR] [--video FILE.mp4] [--view onboard|global|both] [--fps N]
// [--size WxH] [--check]: re-simulates a recorded session.
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <iostream>

#include "app/commands.h"
#include "app/options.h"
#include "trainer/progress.h"
#include "trainer/replay.h"
#include "trainer/strict_json.h"
#include "trainer/world_simulation.h"

namespace colosim::app {

namespace {

struct ReplayOptions {
  std::string session;
  std::string frames;
  std::string video;
  std::string view = "onboard";
  double fps = 30;
  std::string size = "640x480";
  bool check = false;
};

int runReplay(const ReplayOptions& o) {
  // Every input first: the session and its scenario, the frame options, the output folder.
  const ReplayPlan plan = planReplay(o.session);
  const SizePx size = parseSize(o.size, 16);
  if (!o.frames.empty()) checkFramesDir(o.frames);
  if (!o.video.empty()) checkVideoFile(o.video, o.view, size);
  for (const std::string& w : plan.warnings) std::cerr << "colosim: warning: " << w << "\n";
  if (plan.session.truncated) std::cerr << "colosim: " << plan.session.message << "\n";

  std::unique_ptr<Simulation> sim = makeWorldSimulation(plan.scenario);
  const double dt_s = sim->dt_s();
  ProgressBar bar(o.video.empty() ? "replay" : "replay (video)", plan.session.steps, stderrIsTerminal());
  RunHooks hooks;
  hooks.on_progress = [&](long done) { bar.update(done); };
  const std::shared_ptr<FrameExporter> frames = addFrameExport(hooks, o.frames, o.video, o.view, size, o.fps, dt_s);
  const ReplayResult r = replay(plan, *sim, hooks);
  if (frames) frames->finish();
  bar.finish();

  std::printf("colosim replay %s: scenario %s, %ld steps (%.3f s at dt = %g s)%s\n", o.session.c_str(),
              plan.session.header.scenario.c_str(), r.steps, r.steps * dt_s, dt_s,
              r.truncated ? ", TRUNCATED" : "");
  std::printf("  final state hash     %s\n", hashToHex(r.final_state_hash).c_str());
  if (r.final_hash_checked) std::printf("  recorded hash        %s\n", hashToHex(plan.session.final_state_hash).c_str());
  std::printf("  checkpoints checked  %d\n", r.checkpoints_checked);
  std::printf("  replay %s the recording%s\n", r.hashOk() ? "matches" : "DIFFERS FROM",
              r.final_hash_checked ? "" : " (checkpoints only: the session has no end line)");
  if (!r.hashOk()) std::printf("  %s\n", r.mismatch.c_str());
  if (!o.video.empty()) std::printf("  video written in     %s (%ld frames)\n", o.video.c_str(), frames->frames());
  if (o.check && !r.hashOk()) {
    std::cerr << "colosim: --check failed: " << r.mismatch << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

void addReplayCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<ReplayOptions>();
  CLI::App* cmd = app.add_subcommand("replay", "Re-simulate a recorded session from its inputs");
  cmd->add_option("SESSION", o->session, "session file (.jsonl)")->required();
  cmd->add_option("--frames", o->frames, "write frames (PNG) into this new or empty folder");
  cmd->add_option("--video", o->video, "encode the frames (at --fps, --view, --size) into this new video file "
                  "(H.264 in MP4 through FFmpeg; never overwrites a file)");
  cmd->add_option("--view", o->view, "which view the frames show")
      ->check(CLI::IsMember({"onboard", "global", "both"}))->capture_default_str();
  cmd->add_option("--fps", o->fps, "frames per simulated second")->check(CLI::Range(0.1, 1000.0))->capture_default_str();
  cmd->add_option("--size", o->size, "frame size WxH [px]")->capture_default_str();
  cmd->add_flag("--check", o->check, "fail (exit 1) unless the replay reproduces the recorded state hashes");
  cmd->callback([&action, o] { action = [o]() -> int { return runReplay(*o); }; });
}

}  // namespace colosim::app
