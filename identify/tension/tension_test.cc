#include "identify/tension/tension_test.h"

#include <cstdio>
#include <stdexcept>

#include "core/input_error.h"
#include "identify/measurement.h"

namespace colosim {

namespace {

MeasurementSpec tensionSpec() {
  MeasurementSpec spec;
  spec.required_keys = {"experiment", "sample_length_m"};
  spec.columns = {"time_s", "elongation_m", "force_N"};
  spec.min_rows = kMinTensionRows;
  return spec;
}

TensionTest tensionTestOf(const Measurement& m) {
  const std::string& path = m.file;
  if (m.meta("experiment") != "tension")
    throw InputError(path + ": header 'experiment' must be 'tension', got '" + m.meta("experiment") + "'");
  TensionTest t;
  t.file = path;
  t.sample_length_m = m.metaNumber("sample_length_m", 1e-4, 10.0);
  for (const auto& kv : m.metadata)
    if (kv.first != "experiment" && kv.first != "sample_length_m") t.metadata.push_back(kv);
  t.time_s = m.column("time_s");
  t.elongation_m = m.column("elongation_m");
  t.force_N = m.column("force_N");
  return t;
}

}  // namespace

TensionTest readTensionTest(const std::string& path) { return tensionTestOf(readMeasurement(path, tensionSpec())); }

TensionTest parseTensionTest(std::istream& in, const std::string& file) {
  return tensionTestOf(parseMeasurement(in, file, tensionSpec()));
}

void writeTensionTest(const std::string& path, const TensionTest& t) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot write the file");
  std::fprintf(f, "%s\n# experiment: tension\n# sample_length_m: %.6g\n", kMeasurementFormatLine, t.sample_length_m);
  for (const auto& kv : t.metadata) std::fprintf(f, "# %s: %s\n", kv.first.c_str(), kv.second.c_str());
  std::fprintf(f, "time_s,elongation_m,force_N\n");
  for (size_t k = 0; k < t.rows(); ++k)
    std::fprintf(f, "%.4f,%.6f,%.4f\n", t.time_s[k], t.elongation_m[k], t.force_N[k]);
  if (std::fclose(f) != 0) throw std::runtime_error(path + ": cannot write the file");
}

}  // namespace colosim
