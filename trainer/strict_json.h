// Strict reading of JSON input files: unknown keys, missing keys, wrong types, wrong
// units, NaN and out-of-range values are errors naming the file and the key path.
#pragma once

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "core/spline.h"

namespace colosim {

// InputError (bad input, exit code 2) is defined in core/input_error.h.

/// The bytes of a file; InputError "PATH: cannot open file" when it cannot be read.
std::string readTextFile(const std::string& path);

/// Reads and parses a JSON file. Syntax errors (with line and column), duplicate keys,
/// an unreadable file: InputError.
nlohmann::json readJsonFile(const std::string& path);

/// Objects and arrays nested deeper than this are an InputError (colosim's files nest a
/// few levels; deeper input would overflow the stack of code that recurses over values).
constexpr int kMaxJsonDepth = 64;

/// Parses JSON text (for inline tests and for lines of JSON Lines files); `where` is
/// put in front of error messages (for example "session.jsonl:12").
nlohmann::json parseJsonText(const std::string& text, const std::string& where);

/// One JSON object being read: every accessor marks its key as used, and finish()
/// rejects the keys that were never read.
class JsonObject {
 public:
  /// `where` names the file (and line, for JSON Lines); `path` is the key path so far.
  JsonObject(const nlohmann::json& j, std::string where, std::string path = "");

  bool has(const std::string& key) const;
  std::vector<std::string> keys() const;

  const nlohmann::json& raw(const std::string& key);
  double number(const std::string& key, double lo, double hi);
  int integer(const std::string& key, int lo, int hi);
  bool boolean(const std::string& key);
  std::string string(const std::string& key);
  std::string choice(const std::string& key, const std::vector<std::string>& allowed);
  JsonObject object(const std::string& key);
  /// An array of between min_size and max_size entries (of any type; the caller reads
  /// them), else "expected a list of MIN to MAX `entries`".
  const nlohmann::json& list(const std::string& key, size_t min_size, size_t max_size,
                             const std::string& entries = "entries");
  /// A 3-vector of finite numbers.
  Vec3 vec3(const std::string& key, double lo, double hi);
  /// A list of finite numbers in [lo, hi] with between min_size and max_size entries.
  std::vector<double> numbers(const std::string& key, double lo, double hi, size_t min_size,
                              size_t max_size);
  /// A documented quantity {"value": v, "unit": u, "source": s[, "note": t]}: the unit
  /// must be exactly `unit`, the value finite and within [lo, hi].
  double quantity(const std::string& key, const std::string& unit, double lo, double hi);
  /// A documented choice {"value": "name", "source": s[, "note": t]}.
  std::string quantityChoice(const std::string& key, const std::vector<std::string>& allowed);

  /// Reads a file's "format" and "version" keys: the format must be `format` and the version
  /// the one this build reads.
  void formatAndVersion(const std::string& format, int version = 1);

  /// Marks a key as known without reading it (free text such as "note").
  void ignore(const std::string& key);
  /// Throws InputError naming the first key that was never read.
  void finish() const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  const std::string& where() const { return where_; }
  std::string keyPath(const std::string& key) const;

 private:
  const nlohmann::json& j_;
  std::string where_;
  std::string path_;
  std::set<std::string> used_;
};

}  // namespace colosim
