#include "trainer/strict_json.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace colosim {

namespace {

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

nlohmann::json parseJsonText(const std::string& text, const std::string& where) {
  // Duplicate keys are silently merged by nlohmann::json: catch them in the callback.
  std::vector<std::set<std::string>> open_objects;
  std::string duplicate;
  // nlohmann::json parses without recursion, but copying a value and our own scanners
  // (json_position.cc) recurse: deeply nested input ("[[[[...") overflowed the stack. Our
  // files nest a few levels; anything deeper is refused, and not built (the callback
  // discards it) so that nothing recurses over it.
  bool too_deep = false;
  auto callback = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if ((event == E::object_start || event == E::array_start) && depth >= kMaxJsonDepth) {
      too_deep = true;
      return false;
    }
    if (event == E::object_start) {
      open_objects.emplace_back();
    } else if (event == E::object_end) {
      if (!open_objects.empty()) open_objects.pop_back();
    } else if (event == E::key && !open_objects.empty()) {
      const std::string k = parsed.get<std::string>();
      if (!open_objects.back().insert(k).second && duplicate.empty()) duplicate = k;
    }
    return true;
  };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, callback);
  } catch (const nlohmann::json::exception& e) {
    // Syntax errors (with line and column) and numbers too large for a double.
    std::string msg = e.what();
    const auto pos = msg.find("] ");
    throw InputError(where + ": invalid JSON: " + (pos == std::string::npos ? msg : msg.substr(pos + 2)));
  }
  if (too_deep) throw InputError(where + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  if (!duplicate.empty()) throw InputError(where + ": duplicate key '" + duplicate + "'");
  return j;
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream buf;
  buf << in.rdbuf();
  return buf.str();
}

nlohmann::json readJsonFile(const std::string& path) { return parseJsonText(readTextFile(path), path); }

JsonObject::JsonObject(const nlohmann::json& j, std::string where, std::string path)
    : j_(j), where_(std::move(where)), path_(std::move(path)) {
  if (!j_.is_object())
    throw InputError(where_ + ": " + (path_.empty() ? std::string("top level") : path_) +
                     ": expected a JSON object");
}

std::string JsonObject::keyPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonObject::formatAndVersion(const std::string& format, int version) {
  const std::string f = string("format");
  if (f != format) fail("format", "expected '" + format + "', got '" + f + "'");
  const int v = integer("version", 0, 1000000);
  if (v != version)
    fail("version", "unsupported version " + std::to_string(v) + " (this build reads " + std::to_string(version) + ")");
}

void JsonObject::fail(const std::string& key, const std::string& message) const {
  throw InputError(where_ + ": " + keyPath(key) + ": " + message);
}

bool JsonObject::has(const std::string& key) const { return j_.contains(key); }

std::vector<std::string> JsonObject::keys() const {
  std::vector<std::string> k;
  for (auto it = j_.begin(); it != j_.end(); ++it) k.push_back(it.key());
  return k;
}

const nlohmann::json& JsonObject::raw(const std::string& key) {
  if (!j_.contains(key)) {
    std::string unread;  // a typo shows up here as an unread key
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!used_.count(it.key())) unread += (unread.empty() ? "" : ", ") + it.key();
    fail(key, "missing key" + (unread.empty() ? std::string() : " (unread keys here: " + unread + ")"));
  }
  used_.insert(key);
  return j_.at(key);
}

const nlohmann::json& JsonObject::list(const std::string& key, size_t min_size, size_t max_size,
                                       const std::string& entries) {
  const nlohmann::json& v = raw(key);
  if (!v.is_array() || v.size() < min_size || v.size() > max_size)
    fail(key, "expected a list of " + std::to_string(min_size) + " to " + std::to_string(max_size) + " " + entries);
  return v;
}

void JsonObject::ignore(const std::string& key) { used_.insert(key); }

double JsonObject::number(const std::string& key, double lo, double hi) {
  const nlohmann::json& v = raw(key);
  if (!v.is_number()) fail(key, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(key, "not a finite number");
  if (x < lo || x > hi)
    fail(key, formatNumber(x) + " is out of range [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
  return x;
}

int JsonObject::integer(const std::string& key, int lo, int hi) {
  const nlohmann::json& v = raw(key);
  if (!v.is_number_integer()) fail(key, "expected an integer");
  const long long x = v.get<long long>();
  if (x < lo || x > hi)
    fail(key, std::to_string(x) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(x);
}

bool JsonObject::boolean(const std::string& key) {
  const nlohmann::json& v = raw(key);
  if (!v.is_boolean()) fail(key, "expected true or false");
  return v.get<bool>();
}

std::string JsonObject::string(const std::string& key) {
  const nlohmann::json& v = raw(key);
  if (!v.is_string()) fail(key, "expected a string");
  return v.get<std::string>();
}

std::string JsonObject::choice(const std::string& key, const std::vector<std::string>& allowed) {
  const std::string s = string(key);
  for (const std::string& a : allowed)
    if (a == s) return s;
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
  fail(key, "'" + s + "' is not one of: " + list);
}

JsonObject JsonObject::object(const std::string& key) {
  const nlohmann::json& v = raw(key);
  if (!v.is_object()) fail(key, "expected a JSON object");
  return JsonObject(v, where_, keyPath(key));
}

std::vector<double> JsonObject::numbers(const std::string& key, double lo, double hi,
                                        size_t min_size, size_t max_size) {
  const nlohmann::json& v = raw(key);
  if (!v.is_array()) fail(key, "expected a list of numbers");
  if (v.size() < min_size || v.size() > max_size)
    fail(key, "expected " + std::to_string(min_size) + (min_size == max_size ? "" : " to " + std::to_string(max_size)) +
                  " numbers, got " + std::to_string(v.size()));
  std::vector<double> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string k = key + "[" + std::to_string(i) + "]";
    if (!v[i].is_number()) fail(k, "expected a number");
    const double x = v[i].get<double>();
    if (!std::isfinite(x)) fail(k, "not a finite number");
    if (x < lo || x > hi)
      fail(k, formatNumber(x) + " is out of range [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
    out.push_back(x);
  }
  return out;
}

Vec3 JsonObject::vec3(const std::string& key, double lo, double hi) {
  const std::vector<double> v = numbers(key, lo, hi, 3, 3);
  return Vec3(v[0], v[1], v[2]);
}

double JsonObject::quantity(const std::string& key, const std::string& unit, double lo, double hi) {
  JsonObject q = object(key);
  const std::string u = q.string("unit");
  if (u != unit) q.fail("unit", "expected unit '" + unit + "', got '" + u + "'");
  const double v = q.number("value", lo, hi);
  if (q.string("source").empty()) q.fail("source", "a source is required (write 'tuning: why' for chosen values)");
  q.ignore("note");
  q.finish();
  return v;
}

std::string JsonObject::quantityChoice(const std::string& key, const std::vector<std::string>& allowed) {
  JsonObject q = object(key);
  const std::string v = q.choice("value", allowed);
  if (q.string("source").empty()) q.fail("source", "a source is required");
  q.ignore("note");
  q.finish();
  return v;
}

void JsonObject::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it)
    if (!used_.count(it.key())) fail(it.key(), "unknown key");
}

}  // namespace colosim
