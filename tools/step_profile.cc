// step_profile: the world step of `colosim bench contacts` (the scope threaded to the
// caecum, 0.3 s settled), stepped N more times on one lane, for a profiler:
//   valgrind --tool=callgrind --toggle-collect='colosim::stepWorld*' build/tools/step_profile 1000
//   perf record build/tools/step_profile 20000
// Prints the steps taken and the final state hash (the same in every build with the same bits).
#include <cstdio>
#include <cstdlib>

#include "collision/contact_query.h"
#include "trainer/assets.h"

int main(int argc, char** argv) {
  using namespace colosim;
  const long steps = argc > 1 ? std::atol(argv[1]) : 1000;
  if (steps < 0) {
    std::fprintf(stderr, "step_profile: the step count must be >= 0 (got %s)\n", argv[1]);
    return 2;
  }
  const Parameters params = loadParameters(assetPath("params/default.json"));
  const WorldModel m = loadWorldModel(assetPath("anatomy/adult.json"), params);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, m.colon.length_m() - 0.02);
  FclContactQuery q(m);
  const HandleInput hold = s.scope.input;
  for (long k = 0; k < 300 + steps; ++k) stepWorld(m, s, hold, q, 1e-3);
  std::printf("%ld steps (after 300 settling), %zu wall contacts, state hash %016llx\n", steps, s.wall.size(),
              static_cast<unsigned long long>(hashWorldState(s)));
  return 0;
}
