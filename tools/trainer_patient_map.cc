// trainer_patient_map PARAMS.json... [--withdraw-m M] [--withdraw-s S] [--withdraw-turn RAD]
//                     [--abuse [--abuse-anatomy FILE] [--scope-speed-limit V]]
//
// Issue 21's two phenomena on candidate patients (docs/clinical-mechanics.md, session 29):
// for each parameter file, one line with
//   - the hooked untwist (trainer/clinical_manoeuvres.h) with no rotation, clockwise and
//     anticlockwise: the writhe 10 s after the withdrawal began, whether the loop stays,
//     the largest handle torque; "pattern yes" when no rotation leaves the loop and exactly
//     one direction takes it out (LoopMechanics.WithTheTipHookedOnlyOneRotationUndoesTheLoop);
//     after each, how far the hooked tip slid back along the colon;
//   - the hooked withdrawal (withdraw_m over withdraw_s with the handle turned by
//     withdraw_turn_rad; default 0.15 m over 8 s with a quarter turn clockwise, the
//     Pleating test's): the sigmoid's present/rest length when the hook is set and its least,
//     how far the tip slid back;
//   - the steps in which a solver or contact limit engaged, in all four runs;
//   - with --abuse, `extreme_all` and the 8 variants of its script that sessions 27-29
//     measured (times x 0.8-1.2, knobs x 0.6-1; everythingAtOnce, trainer/clinical_manoeuvres.h): per run
//     the limited steps, the steps out of the lumen, the deepest point and the largest track
//     jump, and the sums (docs/hardening.md, session 29).
//     --abuse-anatomy runs them in another anatomy file; --scope-speed-limit sets the scope's
//     solver speed limit (ScopeParams::max_speed_m_per_s, 5 m/s) for them, to see whether a
//     run's figures stand on that limit (docs/clinical-mechanics.md, session 43).
// About 20 s of one core per file; --abuse adds about 10 s.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "trainer/assets.h"
#include "trainer/clinical_manoeuvres.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

int main(int argc, char** argv) {
  using namespace colosim;
  std::vector<std::string> files;
  double withdraw_m = 0.15, withdraw_s = 8.0, withdraw_turn_rad = kHookedWithdrawalTurn_rad;
  bool abuse = false;
  std::string abuse_anatomy;
  double scope_speed_limit_m_per_s = 0;
  CLI::App app{"issue 21's loop pattern and pleating on candidate patients"};
  app.add_option("params", files, "parameter files")->required()->check(CLI::ExistingFile);
  app.add_option("--withdraw-m", withdraw_m, "hooked withdrawal length [m]")->check(CLI::Range(0.0, 0.5));
  app.add_option("--withdraw-s", withdraw_s, "hooked withdrawal duration [s]")->check(CLI::Range(0.5, 60.0));
  app.add_option("--withdraw-turn", withdraw_turn_rad, "the handle's turn during the hooked withdrawal, + clockwise [rad]")
      ->check(CLI::Range(-10.0, 10.0));
  app.add_flag("--abuse", abuse, "also run extreme_all and 8 variants of its script");
  app.add_option("--abuse-anatomy", abuse_anatomy, "the abuse runs' anatomy file (default: extreme_all's)")
      ->check(CLI::ExistingFile);
  app.add_option("--scope-speed-limit", scope_speed_limit_m_per_s,
                 "the scope's solver speed limit in the abuse runs [m/s] (default: the model's)")
      ->check(CLI::Range(0.5, 1000.0));
  CLI11_PARSE(app, argc, argv);
  std::printf("hooked untwist: writhe at 12 s [turns], S = the loop stays, peak handle torque; hooked withdrawal of "
              "%.2f m over %.1f s turning %.2f rad: sigmoid present/rest before -> least, tip back [m]\n",
              withdraw_m, withdraw_s, withdraw_turn_rad);
  for (const std::string& f : files) {
    const Parameters p = loadParameters(f);
    const HookedUntwist none = hookedUntwist(p, 0.0), cw = hookedUntwist(p, -1.0), ccw = hookedUntwist(p, 1.0);
    const HookedWithdrawal w = hookedWithdrawal(p, withdraw_m, withdraw_s, withdraw_turn_rad);
    const bool pattern = none.stays() && cw.stays() != ccw.stays();
    auto mark = [](const HookedUntwist& u) { return u.stays() ? "S" : "-"; };
    std::printf("%s\n  start %+.2f | none %+.2f %s %.3f N m, tip back %.3f m | cw %+.2f %s %.3f N m, %.3f m | ccw %+.2f %s "
                "%.3f N m, %.3f m | pattern %s | sigmoid %.3f -> %.3f, tip back %.3f m | limited steps %ld\n",
                f.c_str(), none.writhe_start, none.writhe_end, mark(none), none.peak_torque_Nm, none.tip_back_m,
                cw.writhe_end, mark(cw), cw.peak_torque_Nm, cw.tip_back_m, ccw.writhe_end, mark(ccw), ccw.peak_torque_Nm,
                ccw.tip_back_m, pattern ? "yes" : "no",
                w.sigmoid_before, w.sigmoid_least, w.tip_back_m,
                none.limited_steps + cw.limited_steps + ccw.limited_steps + w.limited_steps);
    if (!abuse) continue;
    // (time scale, knob scale) of extreme_all's script: the shipped one first.
    const double variants[][2] = {{1.0, 1.0}, {0.8, 0.6}, {0.9, 0.8}, {0.9, 1.0}, {0.95, 0.9},
                                  {1.0, 0.8}, {1.05, 1.0}, {1.1, 0.8}, {1.2, 1.0}};
    long limited = 0, exits = 0;
    Parameters ap = p;
    if (scope_speed_limit_m_per_s > 0) ap.scope.max_speed_m_per_s = scope_speed_limit_m_per_s;
    if (!abuse_anatomy.empty() || scope_speed_limit_m_per_s > 0)
      std::printf("  abuse runs: anatomy %s, scope speed limit %.2f m/s\n",
                  abuse_anatomy.empty() ? "extreme_all's" : abuse_anatomy.c_str(), ap.scope.max_speed_m_per_s);
    for (const auto& v : variants) {
      Scenario sc = everythingAtOnce(v[0], v[1]);
      if (!abuse_anatomy.empty()) sc.anatomy_path = abuse_anatomy;
      WorldSimulation sim(sc, ap);
      const RunResult r = runScenario(sc, sim, nullptr);
      const long l = r.scores["solver_limited_steps"].get<long>(), e = r.scores["lumen_exit_steps"].get<long>();
      limited += l;
      exits += e;
      std::printf("  extreme_all, time x %.2f, knobs x %.1f: limited steps %ld, exit steps %ld, deepest %.2f mm, "
                  "largest track jump %.3f m, peak handle force %.1f N\n",
                  v[0], v[1], l, e, 1e3 * r.scores["max_wall_penetration_m"].get<double>(),
                  r.scores["max_track_jump_m"].get<double>(), r.scores["peak_handle_force_N"].get<double>());
    }
    std::printf("  extreme_all and its 8 variants: limited steps %ld, exit steps %ld\n", limited, exits);
  }
  return 0;
}
