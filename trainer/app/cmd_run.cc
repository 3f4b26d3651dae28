// colosim run [SCENARIO] [--duration S]: runs a scenario headless.
// For now the one scenario is `settle`: the adult colon settling under gravity and its
// mesentery from its rest shape.
#include <cstdio>
#include <iostream>

#include "trainer/app/commands.h"
#include "trainer/assets.h"
#include "trainer/settle.h"
#include "trainer/strict_json.h"
#include "trainer/tension_law_file.h"

namespace colosim::app {

namespace {

struct RunOptions {
  std::string scenario = "settle";
  double duration_s = 10.0;
  double dt_s = 1e-3;
  std::string params;
  std::string anatomy;
  std::string tension_law;  // law file (colosim identify --law-out); empty: the parameters' Voigt law
};

int runSettle(const RunOptions& o) {
  const Parameters params = loadParameters(o.params.empty() ? assetPath("params/default.json") : o.params);
  std::shared_ptr<const TensionLaw> law;
  if (!o.tension_law.empty()) law = loadTensionLaw(o.tension_law);
  const ColonModel model =
      loadColonModel(o.anatomy.empty() ? assetPath("anatomy/adult.json") : o.anatomy, params, law);
  const SettleSummary s = settleColon(model, o.duration_s, o.dt_s);
  std::printf("colosim run settle: adult colon, %d control points over %.3f m, %.1f s at dt = %.4f s (%ld steps)\n",
              s.n_control_points, s.length_m, s.duration_s, s.dt_s, s.steps);
  if (law) {
    std::printf("  tension law          %s from %s:", model.tension_law->name().c_str(), o.tension_law.c_str());
    for (const LawParameter& p : model.tension_law->parameters())
      std::printf(" %s = %.4g %s;", p.name.c_str(), p.value, p.unit.c_str());
    std::printf("\n");
  }
  std::printf("  energy at start      %10.5f J\n", s.energy_start_J);
  std::printf("  energy at end        %10.5f J (kinetic %.3e J)\n", s.energy_end_J, s.kinetic_end_J);
  std::printf("  max displacement     %10.2f mm (in the %s)\n", 1e3 * s.max_displacement_m,
              s.max_displacement_region.c_str());
  std::printf("  max speed at end     %10.3e m/s\n", s.max_speed_end_m_per_s);
  std::printf("  time per step        %10.2f us (median of blocks of 100 steps)\n", s.us_per_step_median);
  std::printf("  state finite         %10s\n", s.finite ? "yes" : "NO");
  return s.finite ? 0 : 1;
}

}  // namespace

void addRunCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scenario headless and print a summary");
  cmd->add_option("SCENARIO", o->scenario, "scenario to run (for now: settle)")->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "simulated time [s]")
      ->check(CLI::Range(1e-3, 1e5))->capture_default_str();
  cmd->add_option("--dt", o->dt_s, "time step [s]")->check(CLI::Range(1e-5, 1e-2))->capture_default_str();
  cmd->add_option("--params", o->params, "parameter file (default: assets/params/default.json)");
  cmd->add_option("--anatomy", o->anatomy, "anatomy file (default: assets/anatomy/adult.json)");
  cmd->add_option("--tension-law", o->tension_law,
                  "tension law file for the colon's tension elements (written by colosim identify --law-out)");
  cmd->callback([&action, o] {
    action = [o]() -> int {
      if (o->scenario != "settle") throw InputError("unknown scenario '" + o->scenario + "' (known: settle)");
      return runSettle(*o);
    };
  });
}

}  // namespace colosim::app
