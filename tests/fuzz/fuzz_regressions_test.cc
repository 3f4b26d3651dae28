// Replays what the fuzzers found (tests/fuzz_regressions/<reader>/: inputs that once
// crashed a reader) and their seed corpora through the same code the fuzzers run
// (readers.h): every kept input must be read or refused with InputError, and every seed
// must read, so that the fuzzers start from files that get past the first checks.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <string_view>

#include <gtest/gtest.h>

#include "fixture.h"
#include "readers.h"
#include "trainer/session.h"
#include "trainer/strict_json.h"

namespace colosim {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Where each fuzzer's seed corpus comes from (the same folders as in scripts/fuzz).
const std::map<std::string, std::vector<std::string>>& seedDirs() {
  static const std::map<std::string, std::vector<std::string>> d = {
      {"parameters", {COLOSIM_ASSET_DIR "/params"}},
      {"anatomy", {COLOSIM_ASSET_DIR "/anatomy"}},
      {"scenario", {COLOSIM_ASSET_DIR "/scenarios"}},
      {"session", {COLOSIM_FUZZ_DIR "/seeds/session"}},
      {"measurement", {COLOSIM_ASSET_DIR "/measurements", COLOSIM_FUZZ_DIR "/seeds/measurement"}},
      {"tension_law", {COLOSIM_FUZZ_DIR "/seeds/tension_law"}}};
  return d;
}

TEST(FuzzRegressions, EveryKeptInputIsReadOrRefused) {
  int replayed = 0;
  for (const fuzz::Reader& r : fuzz::readers()) {
    for (const fs::path& f : filesIn(fs::path(COLOSIM_FUZZ_REGRESSION_DIR) / r.name)) {
      SCOPED_TRACE(f.string());
      try {
        r.read(test::readFile(f.string()));  // true (read) or false (InputError) are both fine
      } catch (const std::exception& e) {
        ADD_FAILURE() << r.name << " reader threw something other than InputError: " << e.what();
      }
      ++replayed;
    }
  }
  std::printf("replayed %d kept fuzz inputs\n", replayed);
}

TEST(FuzzRegressions, EverySeedReads) {
  for (const fuzz::Reader& r : fuzz::readers()) {
    ASSERT_TRUE(seedDirs().count(r.name)) << r.name;
    int seeds = 0;
    for (const std::string& dir : seedDirs().at(r.name)) {
      for (const fs::path& f : filesIn(dir)) {
        const std::string text = test::readFile(f.string());
        // The measurement fuzzer drives the tension-test reader; recorded insertions (the
        // organ-level reader, not fuzzed yet) are refused by it and are no valid seed.
        if (std::string_view(r.name) == "measurement" && text.find("# experiment: insertion") != std::string::npos) continue;
        EXPECT_TRUE(r.read(text)) << r.name << ": " << f;
        ++seeds;
      }
    }
    EXPECT_GT(seeds, 0) << "no seed for the " << r.name << " fuzzer";
  }
}

// The session fuzzer tries each input cut at one point of its own; here every seed session
// is cut at every byte: each prefix reads as a prefix of the recording (no more steps, the
// same inputs) or is refused with InputError, and passes the fuzz harness's checks.
TEST(FuzzRegressions, SeedSessionsCutAtEveryByte) {
  int cuts = 0, read = 0;
  for (const std::string& dir : seedDirs().at("session")) {
    for (const fs::path& f : filesIn(dir)) {
      const std::string text = test::readFile(f.string());
      const Session full = parseSession(text, "seed.jsonl");
      for (size_t k = 0; k <= text.size(); ++k, ++cuts) {
        const std::string cut = text.substr(0, k);
        fuzz::session(cut);  // aborts on a broken invariant
        try {
          const Session p = parseSession(cut, "seed.jsonl");
          ++read;
          ASSERT_LE(p.steps, full.steps) << f << " cut at " << k;
          ASSERT_LE(p.inputs.size(), full.inputs.size()) << f << " cut at " << k;
          for (size_t i = 0; i < p.inputs.size(); ++i) ASSERT_EQ(p.inputs[i].step, full.inputs[i].step);
          ASSERT_EQ(p.complete, full.complete && k + 1 >= text.size()) << f << " cut at " << k;
        } catch (const InputError& e) {
          ASSERT_EQ(std::string(e.what()).rfind("seed.jsonl", 0), 0u) << e.what();
          ASSERT_LT(k, text.find('\n')) << "refused after the header line: " << e.what();
        }
      }
    }
  }
  EXPECT_GT(cuts, 5000);
  EXPECT_GT(read, cuts / 2);
}

}  // namespace
}  // namespace colosim
