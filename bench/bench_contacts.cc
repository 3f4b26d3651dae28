// colosim bench contacts: contact queries in FCL mode against the paper's scan, and the
// whole physics step, with the scope inserted to the caecum (threaded along the colon).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "bench/registry.h"
#include "bench/timing.h"
#include "collision/contact_query.h"
#include "core/step_lanes.h"
#include "trainer/assets.h"

namespace colosim {

BenchOutput benchContacts() {
  const Parameters params = loadParameters(assetPath("params/default.json"));
  const WorldModel m = loadWorldModel(assetPath("anatomy/adult.json"), params);
  WorldState start = makeWorldState(m);
  // The scope to the caecum: threaded along the colon to 2 cm short of the caecal pole,
  // then 0.3 s of simulation so that it rests against the wall.
  threadScopeAlongColon(m, start, m.colon.length_m() - 0.02);
  {
    FclContactQuery q(m);
    const HandleInput hold = start.scope.input;
    for (int k = 0; k < 300; ++k) stepWorld(m, start, hold, q, 1e-3);
  }
  auto queryTime = [&](ContactQuery& q, int blocks, int reps) {
    WorldState s = start;
    return timeBlocks(blocks, reps, [&] {
      q.findWallContacts(m, s);
      q.findSelfContacts(m, s);
    });
  };
  std::vector<std::pair<std::string, BlockTiming>> managers;
  // SaP is left out: with the colon's inflated boxes overlapping their neighbours, its
  // update() (which maintains a list of overlapping pairs) did not finish one step in minutes.
  // Each query by itself: the broadphase updated at every query (no fat bounds), as the
  // scan is; repeated queries of one state would otherwise skip it after the first.
  for (const std::string& name : {std::string("dynamic_aabb_tree"), std::string("interval_tree")}) {
    FclContactQuery q(m, name, 0.0);
    managers.emplace_back(name, queryTime(q, 21, 50));
  }
  ScanContactQuery scan(m);
  const BlockTiming scan_t = queryTime(scan, 7, 3);
  const BlockTiming fcl_t = managers.front().second;
  const double scan_us = scan_t.wall_us, fcl_us = fcl_t.wall_us;

  WorldState s = start;
  FclContactQuery q(m);
  const HandleInput hold = s.scope.input;
  const BlockTiming step_t = timeBlocks(21, 50, [&] { stepWorld(m, s, hold, q, 1e-3); });
  const double step_us = step_t.wall_us;
  size_t contacts = s.wall.size();
  // The same steps with the independent halves on two lanes (core/step_lanes.h), from the
  // same start: the same bits, checked here on the state after the timed steps.
  WorldState s2 = start;
  FclContactQuery q2(m);
  StepLanes lanes;
  const BlockTiming lanes_t = timeBlocks(21, 50, [&] { stepWorld(m, s2, hold, q2, 1e-3, &lanes); });
  // The step with the scope moving (withdrawn at 2 cm/s, turned +-0.5 rad, the tip steered),
  // so that the fat bounds are updated as often as motion makes them: the held scope above
  // rests, and its broadphase is seldom updated.
  auto moving = [&](FclContactQuery& q_moving, long* steps, StepLanes* moving_lanes = nullptr,
                    uint64_t* hash = nullptr) {
    WorldState sm = start;
    long k = 0;
    const BlockTiming t = timeBlocks(21, 50, [&] {
      HandleInput in = hold;
      in.insertion_m -= 0.02 * 1e-3 * static_cast<double>(k);
      in.rotation_rad += 0.5 * std::sin(2e-3 * static_cast<double>(k));
      in.knob_updown_rad = 0.8 * std::sin(3e-3 * static_cast<double>(k));
      ++k;
      stepWorld(m, sm, in, q_moving, 1e-3, moving_lanes);
    });
    *steps = k;
    if (hash) *hash = hashWorldState(sm);
    return t;
  };
  FclContactQuery q3(m), q4(m, "dynamic_aabb_tree", 0.0), q5(m);
  long k3 = 0, k4 = 0, k5 = 0;
  uint64_t hash_one = 0, hash_two = 0;
  const BlockTiming moving_t = moving(q3, &k3, nullptr, &hash_one);
  const BlockTiming moving_every_t = moving(q4, &k4);  // the broadphase updated at every step
  StepLanes moving_lanes;
  const BlockTiming moving_lanes_t = moving(q5, &k5, &moving_lanes, &hash_two);
  const double moving_updates = static_cast<double>(q3.wallRebuilds()) / std::max(1L, k3);
  const bool lanes_same = hashWorldState(s2) == hashWorldState(s) && hash_one == hash_two;
  const double taken_back = static_cast<double>(lanes.callerTookBack()) /
                            std::max(1L, lanes.callerTookBack() + lanes.workerRan());

  BenchOutput out;
  nlohmann::json mgr = nlohmann::json::object();
  for (const auto& [name, t] : managers) mgr[name] = t.wall_us;
  out.json = {{"benchmark", "contacts"},
              {"scope_segments_inside", s.scope.inside},
              {"interaction_points", s.scope.inside * static_cast<int>(m.scope.interaction_points_S.size())},
              {"wall_contacts", contacts},
              {"fcl_query_us", fcl_us},
              {"scan_query_us", scan_us},
              {"ratio", scan_us / fcl_us},
              {"step_us", step_us},
              {"step_two_lanes_us", lanes_t.wall_us},
              {"step_moving_us", moving_t.wall_us},
              {"step_moving_every_update_us", moving_every_t.wall_us},
              {"step_moving_two_lanes_us", moving_lanes_t.wall_us},
              {"broadphase_update_fraction_moving", moving_updates},
              {"broadphase_update_fraction_held", static_cast<double>(q.wallRebuilds()) / (21.0 * 50.0)},
              {"two_lanes_same_state", lanes_same},
              {"two_lanes_taken_back_fraction", taken_back},
              {"cpu", {{"fcl_query_us", fcl_t.cpu_us}, {"scan_query_us", scan_t.cpu_us},
                       {"ratio", scan_t.cpu_us / fcl_t.cpu_us}, {"step_us", step_t.cpu_us},
                       {"step_two_lanes_us", lanes_t.cpu_us}, {"step_moving_us", moving_t.cpu_us},
                       {"step_moving_every_update_us", moving_every_t.cpu_us},
                       {"step_moving_two_lanes_us", moving_lanes_t.cpu_us}}},
              {"fcl_managers_query_us", mgr}};
  char buf[256];
  std::string text = "contacts, adult colon, scope inserted to the caecum (medians):\n";
  std::snprintf(buf, sizeof buf, "  %d scope segments inside, %d interaction points, %zu wall contacts\n",
                s.scope.inside, s.scope.inside * static_cast<int>(m.scope.interaction_points_S.size()), contacts);
  text += buf;
  text += "                                   wall time   thread CPU time\n";
  for (const auto& [name, t] : managers) {
    std::snprintf(buf, sizeof buf, "  FCL query (%-17s) %9.1f us %12.1f us\n", name.c_str(), t.wall_us, t.cpu_us);
    text += buf;
  }
  std::snprintf(buf, sizeof buf, "  paper's scan query            %9.1f us %12.1f us\n  ratio scan / FCL              %9.1f x  %12.1f x\n"
                "  whole physics step            %9.1f us %12.1f us (colon + scope + contacts + self-collision)\n",
                scan_us, scan_t.cpu_us, scan_us / fcl_us, scan_t.cpu_us / fcl_t.cpu_us, step_us, step_t.cpu_us);
  text += buf;
  std::snprintf(buf, sizeof buf, "  the same step on two lanes      %9.1f us %12.1f us (caller thread; state %s; %.0f %% of tasks taken back)\n",
                lanes_t.wall_us, lanes_t.cpu_us, lanes_same ? "identical" : "DIFFERENT", 100 * taken_back);
  text += buf;
  std::snprintf(buf, sizeof buf, "  the step, the scope moving      %9.1f us %12.1f us (broadphase updated in %.0f %% of steps; held: %.0f %%)\n",
                moving_t.wall_us, moving_t.cpu_us, 100 * moving_updates, 100.0 * q.wallRebuilds() / (21.0 * 50.0));
  text += buf;
  std::snprintf(buf, sizeof buf, "  the same, updated every step    %9.1f us %12.1f us\n", moving_every_t.wall_us,
                moving_every_t.cpu_us);
  text += buf;
  std::snprintf(buf, sizeof buf, "  the moving step on two lanes    %9.1f us %12.1f us (caller thread)\n",
                moving_lanes_t.wall_us, moving_lanes_t.cpu_us);
  text += buf;
  out.text = text;
  return out;
}

}  // namespace colosim
