#include "identify/insertion/recording.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "identify/measurement.h"
#include "core/input_error.h"

namespace colosim {

std::vector<std::string> insertionColumns(bool with_tip) {
  std::vector<std::string> c = {"time_s",          "insertion_m",   "rotation_rad",   "knob_updown_rad",
                                "knob_leftright_rad", "handle_force_N", "handle_torque_Nm"};
  if (with_tip) c.insert(c.end(), {"tip_x_m", "tip_y_m", "tip_z_m"});
  return c;
}

std::vector<std::string> insertionTraceColumns() {
  std::vector<std::string> c = insertionColumns(true);
  c.insert(c.end(), {"wall_force_peak_N", "tip_to_caecum_m", "tip_arclength_m", "mesentery_stretch", "loop_turns"});
  return c;
}

namespace {

// The column line of a measurement file (the first line that is not a # line), or "".
std::string columnLine(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the file");
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] != '#') return line;
  }
  return "";
}

}  // namespace

std::string measurementExperiment(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the file");
  std::string line;
  const std::string key = "# experiment:";
  while (std::getline(in, line)) {
    if (line.empty() || line[0] != '#') break;
    if (line.compare(0, key.size(), key) == 0) {
      std::string v = line.substr(key.size());
      while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.erase(v.begin());
      while (!v.empty() && (v.back() == ' ' || v.back() == '\r' || v.back() == '\t')) v.pop_back();
      return v;
    }
  }
  return "";
}

InsertionRecording readInsertionRecording(const std::string& path) {
  // With or without the tip columns: the column line decides which spec applies; the
  // generic reader then checks every column name and row exactly.
  const std::string column_line = columnLine(path);
  const bool with_tip = column_line.find("tip_x_m") != std::string::npos;
  const bool trace = column_line.find("loop_turns") != std::string::npos;
  MeasurementSpec spec;
  spec.required_keys = {"experiment", "scenario"};
  spec.columns = trace ? insertionTraceColumns() : insertionColumns(with_tip);
  spec.min_rows = kMinInsertionRows;
  const Measurement m = readMeasurement(path, spec);
  if (m.meta("experiment") != "insertion")
    throw InputError(path + ": header key 'experiment' is '" + m.meta("experiment") + "', expected 'insertion'");
  InsertionRecording r;
  r.file = path;
  r.metadata = m.metadata;
  r.scenario = m.meta("scenario");
  if (r.scenario.empty()) throw InputError(path + ": header key 'scenario' is empty");
  if (m.hasMeta("params")) {
    r.params = m.meta("params");
    if (r.params.empty()) throw InputError(path + ": header key 'params' is empty");
  }
  r.has_tip = with_tip;
  const size_t n = m.rows();
  r.time_s = m.column("time_s");
  const auto& ins = m.column("insertion_m");
  const auto& rot = m.column("rotation_rad");
  const auto& ud = m.column("knob_updown_rad");
  const auto& lr = m.column("knob_leftright_rad");
  r.force_N = m.column("handle_force_N");
  r.torque_Nm = m.column("handle_torque_Nm");
  auto fail = [&](size_t row, const std::string& msg) {
    throw InputError(path + ":" + std::to_string(m.first_data_line + static_cast<int>(row)) + ": " + msg);
  };
  for (size_t k = 0; k < n; ++k) {
    if (ins[k] < 0 || ins[k] > 3.0) fail(k, "insertion_m out of range [0, 3] m");
    if (std::abs(rot[k]) > 100.0) fail(k, "rotation_rad out of range [-100, 100] rad");
    if (std::abs(ud[k]) > kKnobUpDownMax_rad + 1e-9) fail(k, "knob_updown_rad beyond +-pi");
    if (std::abs(lr[k]) > kKnobLeftRightMax_rad + 1e-9) fail(k, "knob_leftright_rad beyond +-160 deg");
    if (std::abs(r.force_N[k]) > 1000.0) fail(k, "handle_force_N out of range [-1000, 1000] N (wrong unit?)");
    if (std::abs(r.torque_Nm[k]) > 100.0) fail(k, "handle_torque_Nm out of range [-100, 100] N m (wrong unit?)");
    HandleInput in;
    in.insertion_m = ins[k];
    in.rotation_rad = rot[k];
    in.knob_updown_rad = ud[k];
    in.knob_leftright_rad = lr[k];
    r.input.push_back(in);
    if (with_tip) {
      const Vec3 tip(m.column("tip_x_m")[k], m.column("tip_y_m")[k], m.column("tip_z_m")[k]);
      if (tip.cwiseAbs().maxCoeff() > 2.0) fail(k, "tip coordinate out of range [-2, 2] m (wrong unit?)");
      r.tip_m.push_back(tip);
    }
  }
  return r;
}

void writeInsertionRecording(const std::string& path, const InsertionRecording& r) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write the file");
  std::fprintf(f, "%s\n# experiment: insertion\n# scenario: %s\n", kMeasurementFormatLine, r.scenario.c_str());
  if (!r.params.empty()) std::fprintf(f, "# params: %s\n", r.params.c_str());
  for (const auto& kv : r.metadata)
    if (kv.first != "experiment" && kv.first != "scenario" && kv.first != "params")
      std::fprintf(f, "# %s: %s\n", kv.first.c_str(), kv.second.c_str());
  const std::vector<std::string> cols = insertionColumns(r.has_tip);
  for (size_t c = 0; c < cols.size(); ++c) std::fprintf(f, "%s%s", c ? "," : "", cols[c].c_str());
  std::fprintf(f, "\n");
  for (size_t k = 0; k < r.rows(); ++k) {
    const HandleInput& in = r.input[k];
    std::fprintf(f, "%.4f,%.6f,%.5f,%.5f,%.5f,%.4f,%.5f", r.time_s[k], in.insertion_m, in.rotation_rad,
                 in.knob_updown_rad, in.knob_leftright_rad, r.force_N[k], r.torque_Nm[k]);
    if (r.has_tip) std::fprintf(f, ",%.5f,%.5f,%.5f", r.tip_m[k].x(), r.tip_m[k].y(), r.tip_m[k].z());
    std::fprintf(f, "\n");
  }
  if (std::fclose(f) != 0) throw std::runtime_error(path + ": write failed");
}

HandleInput recordedInput(const InsertionRecording& r, double t) {
  if (t <= r.time_s.front()) return r.input.front();
  if (t >= r.time_s.back()) return r.input.back();
  const size_t k = static_cast<size_t>(std::upper_bound(r.time_s.begin(), r.time_s.end(), t) - r.time_s.begin());
  const double a = (t - r.time_s[k - 1]) / (r.time_s[k] - r.time_s[k - 1]);
  const HandleInput &p = r.input[k - 1], &q = r.input[k];
  HandleInput o;
  o.insertion_m = (1 - a) * p.insertion_m + a * q.insertion_m;
  o.rotation_rad = (1 - a) * p.rotation_rad + a * q.rotation_rad;
  o.knob_updown_rad = (1 - a) * p.knob_updown_rad + a * q.knob_updown_rad;
  o.knob_leftright_rad = (1 - a) * p.knob_leftright_rad + a * q.knob_leftright_rad;
  return o;
}

}  // namespace colosim
