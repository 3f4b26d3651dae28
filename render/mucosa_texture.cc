#include "render/mucosa_texture.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/numbers.h"

namespace colosim {

namespace {

// Periodic value noise: a lattice of `cells` x `cells` random values, smoothly
// interpolated, wrapping at the edges so the texture tiles.
class PeriodicNoise {
 public:
  PeriodicNoise(int cells, std::mt19937& rng) : cells_(cells), v_(cells * cells) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double& x : v_) x = u(rng);
  }
  // x, y in [0, 1).
  double operator()(double x, double y) const {
    const double fx = x * cells_, fy = y * cells_;
    const int ix = static_cast<int>(std::floor(fx)), iy = static_cast<int>(std::floor(fy));
    const double tx = fx - ix, ty = fy - iy;
    const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
    auto at = [&](int i, int j) {
      return v_[((j % cells_ + cells_) % cells_) * cells_ + (i % cells_ + cells_) % cells_];
    };
    const double a = at(ix, iy) + sx * (at(ix + 1, iy) - at(ix, iy));
    const double b = at(ix, iy + 1) + sx * (at(ix + 1, iy + 1) - at(ix, iy + 1));
    return a + sy * (b - a);
  }

 private:
  int cells_;
  std::vector<double> v_;
};

struct Walker {
  double x, y, heading, width;
  int steps_left;
};

}  // namespace

Image makeMucosaTexture(const MucosaOptions& options) {
  const int N = std::max(16, options.size_px);
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);

  // Vessel darkness map (0 none .. 1 full vessel), drawn by branching random walks.
  std::vector<float> vessel(static_cast<size_t>(N) * N, 0.0f);
  auto stamp = [&](double cx, double cy, double radius, double strength) {
    const int r = static_cast<int>(std::ceil(radius + 1));
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const double d = std::hypot(dx + std::floor(cx) - cx, dy + std::floor(cy) - cy);
        const double a = std::clamp(radius + 0.5 - d, 0.0, 1.0) * strength;
        if (a <= 0) continue;
        const int x = ((static_cast<int>(std::floor(cx)) + dx) % N + N) % N;  // wrap: tileable
        const int y = ((static_cast<int>(std::floor(cy)) + dy) % N + N) % N;
        float& v = vessel[static_cast<size_t>(y) * N + x];
        v = std::max(v, static_cast<float>(a));
      }
    }
  };
  std::vector<Walker> walkers;
  for (int k = 0; k < options.vessel_count; ++k)
    walkers.push_back({uni(rng) * N, uni(rng) * N, uni(rng) * 2 * kPi, 1.4 + 1.2 * uni(rng),
                       static_cast<int>(N * (0.4 + 0.5 * uni(rng)))});
  std::normal_distribution<double> turn(0.0, 0.12);
  while (!walkers.empty()) {
    Walker w = walkers.back();
    walkers.pop_back();
    for (; w.steps_left > 0 && w.width > 0.35; --w.steps_left) {
      stamp(w.x, w.y, w.width, std::min(1.0, 0.45 + 0.35 * w.width));
      w.heading += turn(rng);
      w.x += std::cos(w.heading);
      w.y += std::sin(w.heading);
      w.width *= 0.9985;
      if (uni(rng) < 0.02) {  // a branch leaves at 25-60 degrees, thinner and shorter
        const double side = uni(rng) < 0.5 ? -1 : 1;
        walkers.push_back({w.x, w.y, w.heading + side * (0.45 + 0.6 * uni(rng)), w.width * 0.65,
                           static_cast<int>(w.steps_left * (0.3 + 0.4 * uni(rng)))});
      }
    }
  }

  PeriodicNoise coarse(6, rng), fine(24, rng), speck(96, rng);
  Image img(N, N);
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x) {
      const double u = static_cast<double>(x) / N, v = static_cast<double>(y) / N;
      // Mucosa: salmon pink with gentle mottling and fine granularity.
      const double m = 0.07 * coarse(u, v) + 0.04 * fine(u, v) + 0.025 * speck(u, v);
      double r = 0.88 + m, g = 0.42 + 0.8 * m, b = 0.35 + 0.6 * m;
      // Vessels: deep red-violet, stronger for the larger ones.
      const double a = 0.6 * vessel[static_cast<size_t>(y) * N + x];
      r = r + a * (0.55 - r);
      g = g + a * (0.13 - g);
      b = b + a * (0.20 - b);
      uint8_t* p = img.at(x, y);
      p[0] = static_cast<uint8_t>(std::lround(std::clamp(r, 0.0, 1.0) * 255));
      p[1] = static_cast<uint8_t>(std::lround(std::clamp(g, 0.0, 1.0) * 255));
      p[2] = static_cast<uint8_t>(std::lround(std::clamp(b, 0.0, 1.0) * 255));
      p[3] = 255;
    }
  }
  return img;
}

}  // namespace colosim
