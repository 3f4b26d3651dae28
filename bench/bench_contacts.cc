// colosim bench contacts: contact queries in FCL mode against the paper's scan, and the
// whole physics step, with the scope inserted to the caecum (threaded along the colon).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <vector>

#include "bench/registry.h"
#include "collision/contact_query.h"
#include "trainer/assets.h"

namespace colosim {

namespace {

// Median microseconds per call over `blocks` blocks of `reps` calls.
double medianMicros(int blocks, int reps, const std::function<void()>& f) {
  std::vector<double> us;
  for (int b = 0; b < blocks; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) f();
    const auto t1 = std::chrono::steady_clock::now();
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / reps);
  }
  std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
  return us[us.size() / 2];
}

}  // namespace

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
    return medianMicros(blocks, reps, [&] {
      q.findWallContacts(m, s);
      q.findSelfContacts(m, s);
    });
  };
  std::vector<std::pair<std::string, double>> managers;
  // SaP is left out: with the colon's inflated boxes overlapping their neighbours, its
  // update() (which maintains a list of overlapping pairs) did not finish one step in minutes.
  for (const std::string& name : {std::string("dynamic_aabb_tree"), std::string("interval_tree")}) {
    FclContactQuery q(m, name);
    managers.emplace_back(name, queryTime(q, 21, 50));
  }
  ScanContactQuery scan(m);
  const double scan_us = queryTime(scan, 7, 3);
  const double fcl_us = managers.front().second;

  WorldState s = start;
  FclContactQuery q(m);
  const HandleInput hold = s.scope.input;
  const double step_us = medianMicros(21, 50, [&] { stepWorld(m, s, hold, q, 1e-3); });
  size_t contacts = s.wall.size();

  BenchOutput out;
  nlohmann::json mgr = nlohmann::json::object();
  for (const auto& [name, us] : managers) mgr[name] = us;
  out.json = {{"benchmark", "contacts"},
              {"scope_segments_inside", s.scope.inside},
              {"interaction_points", s.scope.inside * static_cast<int>(m.scope.interaction_points_S.size())},
              {"wall_contacts", contacts},
              {"fcl_query_us", fcl_us},
              {"scan_query_us", scan_us},
              {"ratio", scan_us / fcl_us},
              {"step_us", step_us},
              {"fcl_managers_query_us", mgr}};
  char buf[256];
  std::string text = "contacts, adult colon, scope inserted to the caecum (medians):\n";
  std::snprintf(buf, sizeof buf, "  %d scope segments inside, %d interaction points, %zu wall contacts\n",
                s.scope.inside, s.scope.inside * static_cast<int>(m.scope.interaction_points_S.size()), contacts);
  text += buf;
  for (const auto& [name, us] : managers) {
    std::snprintf(buf, sizeof buf, "  FCL query (%s): %9.1f us\n", name.c_str(), us);
    text += buf;
  }
  std::snprintf(buf, sizeof buf, "  paper's scan query:      %9.1f us\n  ratio scan / FCL:         %9.1f x\n"
                "  whole physics step:       %9.1f us (colon + scope + contacts + self-collision)\n",
                scan_us, scan_us / fcl_us, step_us);
  text += buf;
  out.text = text;
  return out;
}

}  // namespace colosim
