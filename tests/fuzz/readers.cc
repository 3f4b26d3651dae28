#include "readers.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/extended_tension_law.h"
#include "core/world.h"
#include "identify/tension/tension_test.h"
#include "trainer/assets.h"
#include "trainer/handle_io.h"
#include "trainer/scenario.h"
#include "trainer/session.h"
#include "trainer/strict_json.h"
#include "trainer/tension_law_file.h"

namespace colosim::fuzz {

namespace {

// The name the fuzz input goes by in messages: every InputError must start with it.
const std::string kFile = "fuzz-input";

// A broken invariant: a reader accepted something its callers cannot use.
#define FUZZ_CHECK(cond)                                                                  \
  do {                                                                                    \
    if (!(cond)) {                                                                        \
      std::fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #cond);  \
      std::abort();                                                                       \
    }                                                                                     \
  } while (0)

void checkMessage(const InputError& e) {
  const std::string msg = e.what();
  if (msg.rfind(kFile, 0) != 0) {
    std::fprintf(stderr, "InputError does not name the file: %s\n", msg.c_str());
    std::abort();
  }
}

const Parameters& defaultParameters() {
  static const Parameters p = loadParameters(assetPath("params/default.json"));
  return p;
}

const Anatomy& adultAnatomy() {
  static const Anatomy a = loadAnatomy(assetPath("anatomy/adult.json"));
  return a;
}

// What the simulation relies on in a built colon: finite rest shape, positive radii and
// rest lengths, a mass matrix whose rows sum to a positive mass.
void checkWorld(const WorldModel& w) {
  const ColonModel& m = w.colon;
  FUZZ_CHECK(m.n >= 2);
  FUZZ_CHECK(m.q_rest.allFinite());
  FUZZ_CHECK(m.radius_m.allFinite() && (m.radius_m.array() > 0).all());
  FUZZ_CHECK((m.rest_length_m.array() > 0).all());
  FUZZ_CHECK(m.mass_rowsum_kg.allFinite());
  FUZZ_CHECK(std::isfinite(m.length_m()) && m.length_m() > 0);
}

bool inLimits(const HandleInput& in) {
  return in.insertion_m >= 0 && in.insertion_m <= kInsertionMax_m && std::abs(in.rotation_rad) <= kRotationMax_rad &&
         std::abs(in.knob_updown_rad) <= kKnobUpDownMax_rad && std::abs(in.knob_leftright_rad) <= kKnobLeftRightMax_rad;
}

// Runs `read`, turning InputError into false after checking that it names the file.
template <typename F>
bool guarded(F read) {
  try {
    read();
    return true;
  } catch (const InputError& e) {
    checkMessage(e);
    return false;
  }
}

// A cheap position derived from the bytes (FNV-1a), so that each input is also tried cut
// at a point of its own.
size_t cutPoint(const std::string& data) {
  return data.empty() ? 0 : static_cast<size_t>(hashBytes(data) % (data.size() + 1));
}

}  // namespace

bool parameters(const std::string& data) {
  return guarded([&] {
    const Parameters p = parseParameters(data, kFile);
    FUZZ_CHECK(p.hash == hashBytes(data));
    checkWorld(makeWorldModel(colonModelOf(adultAnatomy(), kFile, p), p.scope, p.contact));
  });
}

bool anatomy(const std::string& data) {
  return guarded([&] {
    const Anatomy a = parseAnatomy(data, kFile);
    const Parameters& p = defaultParameters();
    checkWorld(makeWorldModel(colonModelOf(a, kFile, p), p.scope, p.contact));
  });
}

bool scenario(const std::string& data) {
  return guarded([&] {
    const Scenario s = parseScenario(data, kFile);
    FUZZ_CHECK(!s.script.empty() && s.script.front().t_s == 0.0);
    for (size_t i = 1; i < s.script.size(); ++i) FUZZ_CHECK(s.script[i].t_s > s.script[i - 1].t_s);
    FUZZ_CHECK(s.steps() >= 0);
    // The inputs a run would record must be ones the session reader accepts.
    for (int k = 0; k <= 16; ++k) FUZZ_CHECK(inLimits(scriptedInput(s.script, s.duration_s * k / 16.0)));
  });
}

namespace {

// What replay relies on in a session read without error.
void checkSession(const Session& s) {
  FUZZ_CHECK(s.complete != s.truncated);
  if (s.truncated) FUZZ_CHECK(s.message.rfind(kFile, 0) == 0);
  FUZZ_CHECK(s.header.dt_s > 0);
  FUZZ_CHECK(s.inputs.empty() || s.inputs.front().step == 0);
  for (size_t i = 0; i < s.inputs.size(); ++i) {
    FUZZ_CHECK(inLimits(s.inputs[i].input));
    FUZZ_CHECK(s.inputs[i].step <= s.steps);
    if (i > 0) FUZZ_CHECK(s.inputs[i].step > s.inputs[i - 1].step);
  }
  for (const SessionCheckpoint& c : s.checkpoints) FUZZ_CHECK(c.step > 0 && c.step <= s.steps);
  for (const SessionEvent& e : s.events) FUZZ_CHECK(e.step <= s.steps);
  if (s.complete) FUZZ_CHECK(s.summary.is_object());
}

}  // namespace

bool session(const std::string& data) {
  Session full;
  const bool ok = guarded([&] {
    full = parseSession(data, kFile);
    checkSession(full);
  });
  // The same recording cut off at a point of its own: a prefix of a complete session must
  // replay a prefix of it (never more steps, the same inputs), or be refused.
  const std::string cut = data.substr(0, cutPoint(data));
  guarded([&] {
    const Session p = parseSession(cut, kFile);
    checkSession(p);
    if (ok && full.complete) {
      FUZZ_CHECK(p.steps <= full.steps);
      FUZZ_CHECK(p.inputs.size() <= full.inputs.size());
      for (size_t i = 0; i < p.inputs.size(); ++i) {
        FUZZ_CHECK(p.inputs[i].step == full.inputs[i].step);
        FUZZ_CHECK(sameInput(p.inputs[i].input, full.inputs[i].input));
      }
    }
  });
  return ok;
}

bool measurement(const std::string& data) {
  return guarded([&] {
    std::istringstream in(data);
    const TensionTest t = parseTensionTest(in, kFile);
    FUZZ_CHECK(t.rows() >= kMinTensionRows);
    FUZZ_CHECK(t.elongation_m.size() == t.rows() && t.force_N.size() == t.rows());
    FUZZ_CHECK(std::isfinite(t.sample_length_m) && t.sample_length_m > 0);
    for (size_t k = 0; k < t.rows(); ++k) {
      FUZZ_CHECK(std::isfinite(t.time_s[k]) && std::isfinite(t.elongation_m[k]) && std::isfinite(t.force_N[k]));
      if (k > 0) FUZZ_CHECK(t.time_s[k] > t.time_s[k - 1]);
    }
  });
}

bool tensionLaw(const std::string& data) {
  return guarded([&] {
    const ExtendedLawParams p = parseTensionLawFile(data, kFile);
    const ExtendedTensionLaw law(p);  // must not throw: the reader validated it
    for (const LawParameter& q : law.parameters()) FUZZ_CHECK(std::isfinite(q.value));
    // A stretch to 50 % and back at 1 kHz: forces and stored energy stay finite.
    std::vector<double> z(law.internalSize());
    law.initInternal(z.data());
    const double dt_s = 1e-3;
    double e_prev = 0;
    for (int k = 0; k <= 200; ++k) {
      const double e = 0.5 * (k <= 100 ? k : 200 - k) / 100.0;  // [-]
      const double rate = (e - e_prev) / dt_s;                   // [1/s]
      const TensionResponse r = law.evaluate(e, rate, dt_s, z.data());
      FUZZ_CHECK(std::isfinite(r.force_N));
      FUZZ_CHECK(std::isfinite(law.storedEnergy(e, z.data())));
      law.advance(e, rate, dt_s, z.data());
      e_prev = e;
    }
  });
}

const std::vector<Reader>& readers() {
  static const std::vector<Reader> r = {{"parameters", parameters}, {"anatomy", anatomy},
                                        {"scenario", scenario},     {"session", session},
                                        {"measurement", measurement}, {"tension_law", tensionLaw}};
  return r;
}

}  // namespace colosim::fuzz
