// trainer_patient_map PARAMS.json... [--withdraw-m M] [--withdraw-s S]
//
// Issue 21's two phenomena on candidate patients (docs/clinical-mechanics.md, session 29):
// for each parameter file, one line with
//   - the hooked untwist (trainer/clinical_manoeuvres.h) with no rotation, clockwise and
//     anticlockwise: the writhe 10 s after the withdrawal began, whether the loop stays,
//     the largest handle torque; "pattern yes" when no rotation leaves the loop and exactly
//     one direction takes it out (LoopMechanics.WithTheTipHookedOnlyOneRotationUndoesTheLoop);
//   - the hooked withdrawal (withdraw_m over withdraw_s; default 0.15 m over 8 s, the
//     Pleating test's): the sigmoid's present/rest length when the hook is set and its least,
//     how far the tip slid back;
//   - the steps in which a solver or contact limit engaged, in all four runs.
// About 25 s of one core per file.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "trainer/assets.h"
#include "trainer/clinical_manoeuvres.h"

int main(int argc, char** argv) {
  using namespace colosim;
  std::vector<std::string> files;
  double withdraw_m = 0.15, withdraw_s = 8.0;
  CLI::App app{"issue 21's loop pattern and pleating on candidate patients"};
  app.add_option("params", files, "parameter files")->required()->check(CLI::ExistingFile);
  app.add_option("--withdraw-m", withdraw_m, "hooked withdrawal length [m]")->check(CLI::Range(0.0, 0.5));
  app.add_option("--withdraw-s", withdraw_s, "hooked withdrawal duration [s]")->check(CLI::Range(0.5, 60.0));
  CLI11_PARSE(app, argc, argv);
  std::printf("hooked untwist: writhe at 12 s [turns], S = the loop stays, peak handle torque; hooked withdrawal of "
              "%.2f m over %.1f s: sigmoid present/rest before -> least, tip back [m]\n",
              withdraw_m, withdraw_s);
  for (const std::string& f : files) {
    const Parameters p = loadParameters(f);
    const HookedUntwist none = hookedUntwist(p, 0.0), cw = hookedUntwist(p, 1.0), ccw = hookedUntwist(p, -1.0);
    const HookedWithdrawal w = hookedWithdrawal(p, withdraw_m, withdraw_s);
    const bool pattern = none.stays() && cw.stays() != ccw.stays();
    auto mark = [](const HookedUntwist& u) { return u.stays() ? "S" : "-"; };
    std::printf("%s\n  start %+.2f | none %+.2f %s %.3f N m | cw %+.2f %s %.3f N m | ccw %+.2f %s %.3f N m | pattern %s | "
                "sigmoid %.3f -> %.3f, tip back %.3f m | limited steps %ld\n",
                f.c_str(), none.writhe_start, none.writhe_end, mark(none), none.peak_torque_Nm, cw.writhe_end, mark(cw),
                cw.peak_torque_Nm, ccw.writhe_end, mark(ccw), ccw.peak_torque_Nm, pattern ? "yes" : "no",
                w.sigmoid_before, w.sigmoid_least, w.tip_back_m,
                none.limited_steps + cw.limited_steps + ccw.limited_steps + w.limited_steps);
  }
  return 0;
}
