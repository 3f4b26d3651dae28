#include "core/colon_state.h"

#include <cstring>
#include <stdexcept>

#include "core/colon_model.h"

namespace colosim {

ColonState makeColonState(const ColonModel& model, int load_capacity) {
  ColonState s;
  const int n = model.n;
  s.q = model.q_rest;
  s.v = Points::Zero(3, n);
  s.time_s = 0.0;
  const int zs = model.tension_law->internalSize();
  s.tension_internal.assign(static_cast<size_t>(n - 1) * zs, 0.0);
  for (int e = 0; e + 1 < n && zs > 0; ++e) model.tension_law->initInternal(s.tension_internal.data() + e * zs);
  s.loads.reserve(load_capacity);
  s.tension_force_N = Eigen::VectorXd::Zero(n - 1);
  s.system.resize(3 * n, 11);
  s.constant_system.resize(3 * n, 11);
  s.constant_system_dt_s = -1;
  s.rhs = Eigen::VectorXd::Zero(3 * n);
  s.force = Eigen::VectorXd::Zero(3 * n);
  s.scratch = Eigen::VectorXd::Zero(3 * n);
  return s;
}

std::vector<double> getColonState(const ColonState& state) {
  std::vector<double> out;
  out.reserve(1 + 2 * state.q.size() + state.tension_internal.size());
  out.push_back(state.time_s);
  out.insert(out.end(), state.q.data(), state.q.data() + state.q.size());
  out.insert(out.end(), state.v.data(), state.v.data() + state.v.size());
  out.insert(out.end(), state.tension_internal.begin(), state.tension_internal.end());
  return out;
}

void setColonState(const std::vector<double>& snap, ColonState& state) {
  const size_t want = 1 + 2 * state.q.size() + state.tension_internal.size();
  if (snap.size() != want)
    throw std::invalid_argument("colon state snapshot has " + std::to_string(snap.size()) +
                                " values, expected " + std::to_string(want));
  size_t k = 0;
  state.time_s = snap[k++];
  std::memcpy(state.q.data(), &snap[k], sizeof(double) * state.q.size());
  k += state.q.size();
  std::memcpy(state.v.data(), &snap[k], sizeof(double) * state.v.size());
  k += state.v.size();
  std::copy(snap.begin() + static_cast<long>(k), snap.end(), state.tension_internal.begin());
}

namespace {
void fnv(uint64_t& h, const void* data, size_t bytes) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
}
}  // namespace

uint64_t hashColonState(const ColonState& state) {
  uint64_t h = 14695981039346656037ull;
  fnv(h, &state.time_s, sizeof(double));
  fnv(h, state.q.data(), sizeof(double) * state.q.size());
  fnv(h, state.v.data(), sizeof(double) * state.v.size());
  if (!state.tension_internal.empty())
    fnv(h, state.tension_internal.data(), sizeof(double) * state.tension_internal.size());
  return h;
}

}  // namespace colosim
