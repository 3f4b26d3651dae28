#include "identify/measurement.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "core/input_error.h"

namespace colosim {

namespace {


std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t c = s.find(',', start);
    out.push_back(trim(s.substr(start, c == std::string::npos ? std::string::npos : c - start)));
    if (c == std::string::npos) break;
    start = c + 1;
  }
  return out;
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& msg) {
  throw InputError(file + ":" + std::to_string(line) + ": " + msg);
}

}  // namespace

bool Measurement::hasMeta(const std::string& key) const {
  for (const auto& kv : metadata)
    if (kv.first == key) return true;
  return false;
}

const std::string& Measurement::meta(const std::string& key) const {
  for (const auto& kv : metadata)
    if (kv.first == key) return kv.second;
  throw InputError(file + ": missing header line '# " + key + ": ...'");
}

double Measurement::metaNumber(const std::string& key, double lo, double hi) const {
  const std::string& v = meta(key);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || errno != 0 || !std::isfinite(x) || x < lo || x > hi) {
    throw InputError(file + ": header '" + key + "' must be a number in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + v + "'");
  }
  return x;
}

const std::vector<double>& Measurement::column(const std::string& name) const {
  for (size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return values[c];
  throw InputError(file + ": no column '" + name + "'");
}

Measurement readMeasurement(const std::string& path, const MeasurementSpec& spec) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the file");
  return parseMeasurement(in, path, spec);
}

Measurement parseMeasurement(std::istream& in, const std::string& path, const MeasurementSpec& spec) {
  Measurement m;
  m.file = path;
  std::string line;
  int lineno = 0;
  bool have_columns = false;
  int time_col = -1;
  std::vector<std::string> rows_pending_blank;  // blank lines are allowed only at the end
  int blank_line = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineno == 1) {
      if (trim(line) != kMeasurementFormatLine)
        fail(path, 1, std::string("expected '") + kMeasurementFormatLine + "' as the first line");
      continue;
    }
    if (trim(line).empty()) {
      if (!blank_line) blank_line = lineno;
      continue;
    }
    if (blank_line) fail(path, blank_line, "blank line inside the file");
    if (!have_columns && line[0] == '#') {
      const std::string body = trim(line.substr(1));
      const size_t colon = body.find(':');
      if (colon == std::string::npos || colon == 0)
        fail(path, lineno, "header lines are '# key: value'");
      const std::string key = trim(body.substr(0, colon));
      const std::string value = trim(body.substr(colon + 1));
      for (const auto& kv : m.metadata)
        if (kv.first == key) fail(path, lineno, "header key '" + key + "' appears twice");
      m.metadata.emplace_back(key, value);
      continue;
    }
    if (!have_columns) {
      for (const std::string& key : spec.required_keys)
        if (!m.hasMeta(key)) fail(path, lineno, "missing header line '# " + key + ": ...' before the columns");
      m.columns = splitComma(line);
      std::string expected;
      for (const std::string& c : spec.columns) expected += (expected.empty() ? "" : ",") + c;
      if (m.columns != spec.columns)
        fail(path, lineno, "columns must be '" + expected + "', got '" + trim(line) + "'");
      m.values.assign(m.columns.size(), {});
      for (size_t c = 0; c < m.columns.size(); ++c)
        if (m.columns[c] == "time_s") time_col = static_cast<int>(c);
      have_columns = true;
      m.first_data_line = lineno + 1;
      continue;
    }
    if (line[0] == '#') fail(path, lineno, "header line after the column line");
    const std::vector<std::string> cells = splitComma(line);
    if (cells.size() != m.columns.size())
      fail(path, lineno, "expected " + std::to_string(m.columns.size()) + " values, got " + std::to_string(cells.size()));
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string& cell = cells[c];
      char* end = nullptr;
      errno = 0;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || errno == ERANGE)
        fail(path, lineno, "column '" + m.columns[c] + "': '" + cell + "' is not a number");
      if (!std::isfinite(x)) fail(path, lineno, "column '" + m.columns[c] + "': value is not finite ('" + cell + "')");
      m.values[c].push_back(x);
    }
    if (time_col >= 0) {
      const std::vector<double>& t = m.values[time_col];
      if (t.size() >= 2 && !(t.back() > t[t.size() - 2]))
        fail(path, lineno, "time_s must increase strictly (" + cells[time_col] + " after " +
                               std::to_string(t[t.size() - 2]) + ")");
    }
  }
  if (lineno == 0) throw InputError(path + ":1: empty file");
  if (!have_columns) {
    for (const std::string& key : spec.required_keys)
      if (!m.hasMeta(key)) fail(path, lineno, "missing header line '# " + key + ": ...'");
    fail(path, lineno, "no column line");
  }
  if (m.rows() < spec.min_rows)
    fail(path, lineno, "only " + std::to_string(m.rows()) + " data rows, need at least " +
                           std::to_string(spec.min_rows));
  return m;
}

}  // namespace colosim
