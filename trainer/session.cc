#include "trainer/session.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <streambuf>

#include <zlib.h>

#include "trainer/handle_io.h"
#include "trainer/strict_json.h"

namespace colosim {

std::string withoutGzipSuffix(const std::string& path, bool* compressed) {
  const std::string gz = kGzipSuffix;
  const bool has = path.size() > gz.size() && path.compare(path.size() - gz.size(), gz.size(), gz) == 0;
  if (compressed) *compressed = has;
  return has ? path.substr(0, path.size() - gz.size()) : path;
}

std::string hashToHex(uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

uint64_t readHash(JsonObject& o, const std::string& key) {
  const std::string s = o.string(key);
  if (s.size() != 16 || s.find_first_not_of("0123456789abcdef") != std::string::npos)
    o.fail(key, "expected 16 lowercase hex digits, got '" + s + "'");
  return std::stoull(s, nullptr, 16);
}

// The step of a record and its time, which must agree with the header's dt.
long readStep(JsonObject& o, double dt_s) {
  const long step = o.integer("step", 0, INT_MAX);
  const double t_s = o.number("t_s", 0.0, 1e9);
  if (std::abs(t_s - static_cast<double>(step) * dt_s) > 0.5 * dt_s)
    o.fail("t_s", std::to_string(t_s) + " s does not match step " + std::to_string(step) + " at dt = " +
                      std::to_string(dt_s) + " s");
  return step;
}

SessionHeader readHeader(JsonObject& o) {
  SessionHeader h;
  o.formatAndVersion(kSessionFormat, kSessionVersion);
  h.scenario = o.string("scenario");
  if (h.scenario.empty()) o.fail("scenario", "must not be empty");
  h.scenario_hash = readHash(o, "scenario_hash");
  h.params_hash = readHash(o, "params_hash");
  if (o.has("params")) {
    h.params = o.string("params");
    if (h.params.empty()) o.fail("params", "must not be empty (leave the key out for the scenario's own file)");
  }
  h.anatomy_hash = readHash(o, "anatomy_hash");
  if (o.has("scope_hash")) h.scope_hash = readHash(o, "scope_hash");
  if (o.has("scope")) {
    h.scope = o.string("scope");
    if (h.scope.empty()) o.fail("scope", "must not be empty (leave the key out for the scenario's own design)");
  }
  h.colosim_version = o.string("colosim_version");
  h.dt_s = o.number("dt_s", 1e-5, 1e-2);
  h.seed = o.integer("seed", 0, INT_MAX);
  h.mode = o.choice("mode", {"scripted", "interactive"});
  if (o.has("patient_position"))
    h.patient_position = o.choice("patient_position", {"left_lateral", "right_lateral", "supine", "prone"});
  return h;
}

}  // namespace

namespace {

// Reads line by line (an hour at 1 kHz is hundreds of MB: never the whole text at once).
// ends_only: the header and the last line only, the lines between skipped unread.
Session parseSessionStream(std::istream& in, const std::string& file, bool ends_only = false) {
  Session s;
  s.file = file;
  if (in.peek() == std::char_traits<char>::eof()) throw InputError(file + ": empty file: not a session (no header line)");

  bool have_header = false;
  long last_step = 0;        // largest step of any record so far
  int last_complete_line = 0;
  std::string content;
  for (int line = 1; std::getline(in, content); ++line) {
    // getline stops at end of file without a newline only on the last, cut-off line.
    const bool has_newline = !in.eof();
    const std::string where = file + ":" + std::to_string(line);
    if (ends_only && line > 1 && in.peek() != std::char_traits<char>::eof()) {
      last_complete_line = s.lines = line;  // a line between: not read
      continue;
    }

    if (s.complete) throw InputError(where + ": content after the end line");
    if (content.empty()) throw InputError(where + ": empty line");
    nlohmann::json j;
    try {
      j = parseJsonText(content, where);
    } catch (const InputError& e) {
      if (has_newline) throw;
      // The last line, without its newline and not valid JSON: the file was cut off here.
      if (!have_header) throw InputError(where + ": the header line is cut off: nothing to replay");
      s.truncated = true;
      s.message = where + ": the last line is cut off (the recording stopped mid-line); replaying the " +
                  std::to_string(last_complete_line) + " complete lines, " + std::to_string(last_step) + " steps";
      break;
    }
    const bool end_line = j.is_object() && j.contains("type") && j["type"].is_string() && j["type"] == "end";
    if (ends_only && line > 1 && !end_line) {
      last_complete_line = s.lines = line;  // the last line, not an end line: the session is cut
      continue;
    }
    JsonObject o(j, where);
    const std::string type = o.choice("type", {"header", "input", "assist", "event", "checkpoint", "end"});
    if (!have_header && type != "header") o.fail("type", "the first line must be the header, got '" + type + "'");
    if (have_header && type == "header") o.fail("type", "a second header");

    if (type == "header") {
      s.header = readHeader(o);
      have_header = true;
    } else if (type == "input") {
      SessionInput in;
      in.line = line;
      in.step = readStep(o, s.header.dt_s);
      if (s.inputs.empty() && in.step != 0) o.fail("step", "the first input must be at step 0");
      if (!s.inputs.empty() && in.step <= s.inputs.back().step)
        o.fail("step", "input steps must increase strictly (previous input: step " +
                           std::to_string(s.inputs.back().step) + ")");
      if (in.step < last_step)
        o.fail("step", "steps must not decrease (previous line: step " + std::to_string(last_step) + ")");
      in.input = readHandleInput(o);
      s.inputs.push_back(in);
      last_step = in.step;
    } else if (type == "assist") {
      SessionAssist a;
      a.line = line;
      a.step = readStep(o, s.header.dt_s);
      if (!s.assists.empty() && a.step <= s.assists.back().step)
        o.fail("step", "assist steps must increase strictly (previous assist: step " +
                           std::to_string(s.assists.back().step) + ")");
      if (a.step < last_step)
        o.fail("step", "steps must not decrease (previous line: step " + std::to_string(last_step) + ")");
      a.assist.abdominal_pressure = o.boolean("abdominal_pressure");
      a.assist.patient_position = o.choice("patient_position", {"left_lateral", "right_lateral", "supine", "prone"});
      s.assists.push_back(a);
      last_step = a.step;
    } else if (type == "event") {
      SessionEvent e;
      e.line = line;
      e.step = readStep(o, s.header.dt_s);
      if (e.step < last_step)
        o.fail("step", "steps must not decrease (previous line: step " + std::to_string(last_step) + ")");
      e.name = o.string("name");
      if (e.name.empty() || e.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
        o.fail("name", "expected a lowercase identifier, got '" + e.name + "'");
      if (o.has("detail")) e.detail = o.string("detail");
      s.events.push_back(e);
      last_step = e.step;
    } else if (type == "checkpoint") {
      SessionCheckpoint c;
      c.line = line;
      c.step = readStep(o, s.header.dt_s);
      if (c.step <= 0) o.fail("step", "a checkpoint comes after at least one step");
      if (c.step < last_step || (!s.checkpoints.empty() && c.step <= s.checkpoints.back().step))
        o.fail("step", "checkpoint steps must increase (previous line: step " + std::to_string(last_step) + ")");
      c.state_hash = readHash(o, "state_hash");
      s.checkpoints.push_back(c);
      last_step = c.step;
    } else {  // end
      const long steps = readStep(o, s.header.dt_s);
      if (steps < last_step)
        o.fail("step", "the session ends at step " + std::to_string(steps) + ", before its last record (step " +
                           std::to_string(last_step) + ")");
      if (steps > 0 && s.inputs.empty() && !ends_only)
        o.fail("step", "steps were simulated but no input was recorded");
      s.final_state_hash = readHash(o, "state_hash");
      const nlohmann::json& summary = o.raw("summary");
      if (!summary.is_object()) o.fail("summary", "expected a JSON object");
      s.summary = summary;
      s.complete = true;
      last_step = steps;
    }
    o.finish();
    last_complete_line = line;
    s.lines = line;
  }
  if (!have_header) throw InputError(file + ": no header line: not a session");
  s.steps = last_step;
  if (!s.complete) {
    s.truncated = true;
    if (s.message.empty())
      s.message = file + ":" + std::to_string(last_complete_line) +
                  ": no end line (the recording stopped, for example in a crash); replaying the " +
                  std::to_string(last_complete_line) + " complete lines, " + std::to_string(last_step) + " steps";
  }
  return s;
}

}  // namespace

Session parseSession(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  return parseSessionStream(in, file);
}

namespace {

// A read-only stream buffer over zlib's gz reader: a gzip-compressed session
// (NAME.jsonl.gz, e.g. the shipped expert sessions) reads like a plain one, and a plain
// file passes through unchanged (zlib reads it as is). A file cut inside its gzip stream
// reads as far as it goes: the session parser then sees a cut-off recording.
class GzReadBuffer : public std::streambuf {
 public:
  explicit GzReadBuffer(const std::string& path) : f_(gzopen(path.c_str(), "rb")) {}
  ~GzReadBuffer() override {
    if (f_) gzclose(f_);
  }
  GzReadBuffer(const GzReadBuffer&) = delete;
  GzReadBuffer& operator=(const GzReadBuffer&) = delete;
  bool isOpen() const { return f_ != nullptr; }
  /// zlib's message when the data could not be decompressed (not a cut), else "".
  const std::string& error() const { return error_; }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    const int n = gzread(f_, buffer_, sizeof buffer_);
    if (n <= 0) {
      int code = Z_OK;
      const char* message = gzerror(f_, &code);
      if (n < 0 && code != Z_BUF_ERROR) error_ = message ? message : "gzip error";
      return traits_type::eof();
    }
    setg(buffer_, buffer_, buffer_ + n);
    return traits_type::to_int_type(*gptr());
  }

 private:
  gzFile f_;
  char buffer_[1 << 16];
  std::string error_;
};

Session readSessionFile(const std::string& path, bool ends_only) {
  GzReadBuffer buffer(path);
  if (!buffer.isOpen()) throw InputError(path + ": cannot open file");
  std::istream in(&buffer);
  Session s;
  try {
    s = parseSessionStream(in, path, ends_only);
  } catch (const InputError&) {
    if (buffer.error().empty()) throw;  // else the parser choked on what zlib could not decompress
  }
  if (!buffer.error().empty()) throw InputError(path + ": not a readable gzip file: " + buffer.error());
  return s;
}

}  // namespace

Session readSession(const std::string& path) { return readSessionFile(path, false); }

Session readSessionEnds(const std::string& path) { return readSessionFile(path, true); }

// ---------------------------------------------------------------------------------------

SessionWriter::SessionWriter(const std::string& path, const SessionHeader& header)
    : path_(path), header_(header) {
  if (!(header.dt_s > 0)) throw std::invalid_argument("SessionWriter: dt_s must be positive");
  checkpoint_steps_ = std::max(1L, std::lround(1.0 / header.dt_s));
  bool compressed = false;
  withoutGzipSuffix(path, &compressed);
  if (compressed) {
    gz_ = gzopen(path.c_str(), "wb6");
    if (!gz_) throw std::runtime_error(path + ": cannot open for writing");
  } else {
    f_ = std::fopen(path.c_str(), "wb");
    if (!f_) throw std::runtime_error(path + ": cannot open for writing");
  }
  nlohmann::json j;
  j["type"] = "header";
  j["format"] = kSessionFormat;
  j["version"] = kSessionVersion;
  j["scenario"] = header.scenario;
  j["scenario_hash"] = hashToHex(header.scenario_hash);
  j["params_hash"] = hashToHex(header.params_hash);
  if (!header.params.empty()) j["params"] = header.params;
  j["anatomy_hash"] = hashToHex(header.anatomy_hash);
  if (header.scope_hash != 0) j["scope_hash"] = hashToHex(header.scope_hash);
  if (!header.scope.empty()) j["scope"] = header.scope;
  j["colosim_version"] = header.colosim_version;
  j["dt_s"] = header.dt_s;
  j["seed"] = header.seed;
  j["mode"] = header.mode;
  if (!header.patient_position.empty()) j["patient_position"] = header.patient_position;
  writeLine(j);
  flush();
}

SessionWriter::~SessionWriter() {
  close();  // no end line: the file reads as truncated, which it is
}

void SessionWriter::writeLine(const nlohmann::json& j) {
  if (!isOpen()) throw std::logic_error("SessionWriter: writing after end()");
  const std::string line = j.dump() + "\n";
  const bool ok = gz_ ? gzwrite(gz_, line.data(), static_cast<unsigned>(line.size())) == static_cast<int>(line.size())
                      : std::fwrite(line.data(), 1, line.size(), f_) == line.size();
  if (!ok) throw std::runtime_error(path_ + ": write failed");
}

void SessionWriter::flush() {
  if (gz_) gzflush(gz_, Z_SYNC_FLUSH);
  else if (f_) std::fflush(f_);
}

bool SessionWriter::close() {
  bool ok = true;
  if (gz_) ok = gzclose(gz_) == Z_OK;
  if (f_) ok = std::fclose(f_) == 0;
  gz_ = nullptr;
  f_ = nullptr;
  return ok;
}

void SessionWriter::input(long step, const HandleInput& in) {
  if (have_input_ && sameInput(in, last_input_)) return;
  if (step <= last_step_ && have_input_) throw std::logic_error("SessionWriter: input steps must increase");
  nlohmann::json j;
  j["type"] = "input";
  j["step"] = step;
  j["t_s"] = static_cast<double>(step) * header_.dt_s;
  writeHandleInput(j, in);
  writeLine(j);
  have_input_ = true;
  last_input_ = in;
  last_step_ = step;
}

void SessionWriter::assist(long step, const AssistInput& a) {
  if (a == last_assist_) return;
  if (a.patient_position.empty()) throw std::logic_error("SessionWriter: an assist line names the patient position");
  if (step <= last_assist_step_) throw std::logic_error("SessionWriter: assist steps must increase");
  nlohmann::json j;
  j["type"] = "assist";
  j["step"] = step;
  j["t_s"] = static_cast<double>(step) * header_.dt_s;
  j["abdominal_pressure"] = a.abdominal_pressure;
  j["patient_position"] = a.patient_position;
  writeLine(j);
  flush();
  last_assist_ = a;
  last_assist_step_ = step;
}

void SessionWriter::event(long steps_done, const std::string& name, const std::string& detail) {
  nlohmann::json j;
  j["type"] = "event";
  j["step"] = steps_done;
  j["t_s"] = static_cast<double>(steps_done) * header_.dt_s;
  j["name"] = name;
  if (!detail.empty()) j["detail"] = detail;
  writeLine(j);
  flush();
}

void SessionWriter::checkpoint(long steps_done, uint64_t state_hash) {
  nlohmann::json j;
  j["type"] = "checkpoint";
  j["step"] = steps_done;
  j["t_s"] = static_cast<double>(steps_done) * header_.dt_s;
  j["state_hash"] = hashToHex(state_hash);
  writeLine(j);
  flush();
}

void SessionWriter::end(long steps_done, uint64_t state_hash, const nlohmann::json& summary) {
  nlohmann::json j;
  j["type"] = "end";
  j["step"] = steps_done;
  j["t_s"] = static_cast<double>(steps_done) * header_.dt_s;
  j["state_hash"] = hashToHex(state_hash);
  j["summary"] = summary.is_object() ? summary : nlohmann::json::object();
  writeLine(j);
  if (!close()) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace colosim
