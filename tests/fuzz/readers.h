// One fuzz input through one of colosim's file readers, shared by the libFuzzer targets
// (fuzz_<reader>.cc) and by the regression test that replays the inputs they once crashed
// on (tests/fuzz_regressions/<reader>/, fuzz_regressions_test.cc).
//
// Each function reads `data` as the whole content of a file of that kind, through the same
// code the path-taking reader uses. Bad input must end in InputError (the function then
// returns false); a file that reads is checked further (what a caller relies on: finite
// values, ordered steps, a model that can be built) and gives true. Anything else - another
// exception, a broken invariant (reported on stderr, then abort()), a sanitizer report - is
// a bug in the reader.
#pragma once

#include <string>
#include <vector>

namespace colosim::fuzz {

bool parameters(const std::string& data);   ///< parameter file, then the adult colon and world built with it
bool anatomy(const std::string& data);      ///< anatomy file, then its colon and world with the default parameters
bool scenario(const std::string& data);     ///< scenario file, then its scripted inputs
bool session(const std::string& data);      ///< session file, and a prefix of it (a cut-off recording)
bool measurement(const std::string& data);  ///< tension-test measurement file
bool tensionLaw(const std::string& data);   ///< tension law file, then the law evaluated

/// The readers by name (the folder names under tests/fuzz_regressions/ and of the fuzzers).
struct Reader {
  const char* name;
  bool (*read)(const std::string& data);
};
const std::vector<Reader>& readers();

}  // namespace colosim::fuzz
