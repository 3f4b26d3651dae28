// Is the organ replay converged? How far the paper's model's handle force moves when the
// time step or the resolution is refined, against the sensor noise an identification has
// to see effects through (docs/organ-identification.md, "Convergence"):
//   organ_convergence [--seed N] [--duration S] [--dt LIST] [--spacing LIST] [--relax S]
//                     [--wall-per-point]
// draws the organ trials' two-rate insertion for the seed (no hidden effect;
// identify/insertion/synthetic.h drawTwoRateInsertion), makes its inputs with the bench
// scenario at its own time step and resolution, then replays them with the paper's model
// (replayInsertion, no extension) at every time step of --dt (at the first spacing) and
// at every spacing of --spacing (colon control points and scope segments alike, at the
// first time step). It prints, for each replay, its cost and the RMS difference of its
// handle force from the finest replay of the same list and from the next finer one, with
// the mean difference removed (an identification fits an offset) [N], the median absolute
// difference from the finest (blind to the rows of an input's velocity jump) [N]; and the
// recording's sensor noise for scale. --relax S lets the world rest S seconds with the
// handle held before the recording starts; --wall-per-point replays with the paper's wall,
// stiff per interaction point whatever the slice length, instead of per length of scope
// (ContactParams::wall_reference_slice_m), data and replays alike.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "identify/insertion/replay.h"
#include "identify/insertion/synthetic.h"
#include "identify/selection.h"
#include "trainer/scenario.h"

using namespace colosim;

namespace {

// RMS of a - b about its mean [N].
double rmsAboutMean(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = a.size();
  double mean = 0;
  for (size_t i = 0; i < n; ++i) mean += a[i] - b[i];
  mean /= static_cast<double>(n);
  double ss = 0;
  for (size_t i = 0; i < n; ++i) ss += (a[i] - b[i] - mean) * (a[i] - b[i] - mean);
  return std::sqrt(ss / static_cast<double>(n));
}

// Median of |a - b - median(a - b)| [N]: the typical difference, blind to the few rows
// where an input's velocity jumps and the grip's inertial impulse grows as 1 / dt.
double medianAbsAboutMedian(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d(a.size());
  for (size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  const double m = upperMedian(d);
  for (double& x : d) x = std::abs(x - m);
  return upperMedian(d);
}

struct Replay {
  double dt_s = 0, spacing_m = 0, cost_s = 0;
  std::vector<double> force_N;
};

void printList(const char* what, const std::vector<Replay>& list, double noise_N) {
  std::printf("%s\n%10s %10s %8s %14s %14s %16s\n", what, "dt_s", "spacing_m", "cost_s", "vs_finest_N", "vs_next_N",
              "median_vs_finest_N");
  for (size_t i = 0; i < list.size(); ++i) {
    const Replay& r = list[i];
    std::printf("%10.6f %10.5f %8.1f", r.dt_s, r.spacing_m, r.cost_s);
    if (i + 1 < list.size()) {
      const double finest = rmsAboutMean(r.force_N, list.back().force_N);
      const double next = rmsAboutMean(r.force_N, list[i + 1].force_N);
      const double typical = medianAbsAboutMedian(r.force_N, list.back().force_N);
      std::printf(" %7.3f (%4.1fx) %7.3f (%4.1fx) %7.3f (%4.1fx)\n", finest, finest / noise_N, next, next / noise_N,
                  typical, typical / noise_N);
    } else {
      std::printf(" %14s %14s\n", "(finest)", "-");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"How far the organ replay moves when the time step or the resolution is refined"};
  uint64_t seed = 1001;
  double duration_s = 2.0;
  std::vector<double> dts{0.001, 0.0005, 0.00025};
  std::vector<double> spacings{0.015, 0.0075};
  double relax_s = -1;
  bool wall_per_point = false;
  app.add_option("--seed", seed, "seed of the two-rate insertion (as organ_trials)");
  app.add_option("--duration", duration_s, "recording length [s]")->check(CLI::Range(0.5, 60.0));
  app.add_option("--dt", dts, "time steps, coarse to fine [s]")->delimiter(',')->check(CLI::Range(1e-5, 1e-2));
  app.add_option("--spacing", spacings, "control-point and scope-segment spacings, coarse to fine [m]")
      ->delimiter(',')
      ->check(CLI::Range(0.002, 0.06));
  app.add_option("--relax", relax_s,
                 "seconds the world rests with the handle held before the recording starts, in the data and "
                 "every replay (default: the scenario's start specification)")
      ->check(CLI::Range(0.0, 60.0));
  app.add_flag("--wall-per-point", wall_per_point,
               "the wall's stiffness per interaction point whatever the slice length (wall_reference_slice_length 0)");
  CLI11_PARSE(app, argc, argv);

  ReplaySetup base = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
  base.relax_s = relax_s;
  if (wall_per_point) base.params.contact.wall_reference_slice_m = 0;
  const SyntheticInsertionSpec spec = drawTwoRateInsertion(seed, -1, duration_s);
  const InsertionRecording rec = makeSyntheticInsertion(base, spec);
  std::printf("seed %llu, %.1f s, %zu rows; made at dt %.4f s, spacing %.4f m; sensor noise %.3f N\n",
              static_cast<unsigned long long>(seed), duration_s, rec.rows(), base.dt_s,
              base.params.colon.control_point_spacing_m, spec.force_noise_N);

  auto replay = [&](double dt_s, double spacing_m) {
    ReplaySetup s = base;
    if (spacing_m > 0) {
      s.params.colon.control_point_spacing_m = spacing_m;
      s.params.scope.segment_length_m = spacing_m;
    }
    s.dt_s = dt_s;
    const auto t0 = std::chrono::steady_clock::now();
    Replay r;
    r.dt_s = dt_s;
    r.spacing_m = spacing_m;
    r.force_N = replayInsertion(s, rec, OrganParams{}).force_N;
    r.cost_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };
  std::vector<Replay> by_dt, by_spacing;
  for (double dt : dts) by_dt.push_back(replay(dt, spacings.front()));
  by_spacing.push_back(by_dt.front());  // the first time step at the first spacing
  for (size_t i = 1; i < spacings.size(); ++i) by_spacing.push_back(replay(dts.front(), spacings[i]));
  printList("time step (first spacing):", by_dt, spec.force_noise_N);
  printList("spacing (first time step):", by_spacing, spec.force_noise_N);
  return 0;
}
