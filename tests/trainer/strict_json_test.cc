// Strict JSON parsing: limits that keep hostile input from crashing the readers.
#include "trainer/strict_json.h"

#include <string>

#include <gtest/gtest.h>

namespace colosim {
namespace {

std::string nested(int levels) { return std::string(levels, '[') + std::string(levels, ']'); }

TEST(StrictJson, NestingUpToTheLimitParses) {
  const nlohmann::json j = parseJsonText(nested(kMaxJsonDepth), "f.json");
  int depth = 0;
  for (const nlohmann::json* v = &j; v->is_array(); v = v->empty() ? nullptr : &(*v)[0]) {
    ++depth;
    if (v->empty()) break;
  }
  EXPECT_EQ(depth, kMaxJsonDepth);
}

// Found by hand while hardening (docs/hardening.md): 100,000 levels overflowed the stack
// when a session's summary was copied or a scenario's error message was located.
TEST(StrictJson, DeeperNestingIsAnInputErrorNamingTheFile) {
  for (const int levels : {kMaxJsonDepth + 1, 100000}) {
    for (const std::string& text : {nested(levels), "{\"summary\": " + nested(levels) + "}"}) {
      try {
        parseJsonText(text, "f.json:3");
        ADD_FAILURE() << levels << " levels parsed";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "f.json:3: JSON nested deeper than 64 levels");
      }
    }
  }
}

}  // namespace
}  // namespace colosim
