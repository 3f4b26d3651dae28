#include "trainer/json_position.h"

#include <cctype>
#include <cstring>
#include <map>

namespace colosim {

namespace {

// A small scanner over JSON text that records the line of every key path. It trusts the
// text to be valid JSON (callers parse it first) and stops quietly on anything odd.
class Scanner {
 public:
  explicit Scanner(const std::string& t) : t_(t) {}
  std::map<std::string, int> lines;

  bool value(const std::string& path) {
    ws();
    if (i_ >= t_.size()) return false;
    const char c = t_[i_];
    if (c == '{') return object(path);
    if (c == '[') return array(path);
    if (c == '"') return string(nullptr);
    while (i_ < t_.size() && !std::strchr(",]}", t_[i_]) && !std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
    return true;
  }

 private:
  void ws() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) {
      if (t_[i_] == '\n') ++line_;
      ++i_;
    }
  }
  bool string(std::string* out) {
    ++i_;  // opening quote
    while (i_ < t_.size() && t_[i_] != '"') {
      if (t_[i_] == '\\') {
        if (out && i_ + 1 < t_.size()) out->push_back(t_[i_ + 1]);  // escapes: good enough for key names
        i_ += 2;
        continue;
      }
      if (out) out->push_back(t_[i_]);
      ++i_;
    }
    if (i_ >= t_.size()) return false;
    ++i_;
    return true;
  }
  bool object(const std::string& path) {
    ++i_;
    ws();
    if (i_ < t_.size() && t_[i_] == '}') { ++i_; return true; }
    while (i_ < t_.size()) {
      ws();
      if (i_ >= t_.size() || t_[i_] != '"') return false;
      std::string key;
      const int key_line = line_;
      if (!string(&key)) return false;
      const std::string p = path.empty() ? key : path + "." + key;
      lines.emplace(p, key_line);
      ws();
      if (i_ >= t_.size() || t_[i_] != ':') return false;
      ++i_;
      if (!value(p)) return false;
      ws();
      if (i_ >= t_.size()) return false;
      if (t_[i_] == ',') { ++i_; continue; }
      if (t_[i_] == '}') { ++i_; return true; }
      return false;
    }
    return false;
  }
  bool array(const std::string& path) {
    ++i_;
    ws();
    if (i_ < t_.size() && t_[i_] == ']') { ++i_; return true; }
    for (int k = 0; i_ < t_.size(); ++k) {
      ws();
      const std::string p = path + "[" + std::to_string(k) + "]";
      lines.emplace(p, line_);
      if (!value(p)) return false;
      ws();
      if (i_ >= t_.size()) return false;
      if (t_[i_] == ',') { ++i_; continue; }
      if (t_[i_] == ']') { ++i_; return true; }
      return false;
    }
    return false;
  }

  const std::string& t_;
  size_t i_ = 0;
  int line_ = 1;
};

}  // namespace

int lineOfKeyPath(const std::string& text, const std::string& path) {
  Scanner s(text);
  s.value("");
  std::string p = path;
  while (!p.empty()) {
    const auto it = s.lines.find(p);
    if (it != s.lines.end()) return it->second;
    // Up one level: drop a trailing "[i]" or ".key".
    const auto cut = p.find_last_of(".[");
    if (cut == std::string::npos) break;
    p = p.substr(0, cut);
  }
  return 0;
}

std::string addLineToMessage(const std::string& message, const std::string& file,
                             const std::string& text) {
  const std::string prefix = file + ": ";
  if (message.compare(0, prefix.size(), prefix) != 0) return message;
  const std::string rest = message.substr(prefix.size());
  const auto colon = rest.find(": ");
  if (colon == std::string::npos) return message;
  std::string path = rest.substr(0, colon);
  if (!path.empty() && path.back() == '.') path.pop_back();  // fail("", ...) on a nested object
  const int line = lineOfKeyPath(text, path);
  if (line <= 0) return message;
  return file + ":" + std::to_string(line) + ": " + rest;
}

}  // namespace colosim
