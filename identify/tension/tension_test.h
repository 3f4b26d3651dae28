// Tension tests (docs/identification.md, "The measurement format"): the measurement format
// of identify/measurement.h with `# experiment: tension`, `# sample_length_m: L` and the
// columns time_s,elongation_m,force_N.
#pragma once

#include <istream>
#include <string>
#include <utility>
#include <vector>

namespace colosim {

/// A displacement-controlled tension test (`# experiment: tension`).
struct TensionTest {
  std::string file;
  std::vector<std::pair<std::string, std::string>> metadata;
  double sample_length_m = 0;         ///< rest length L of the sample [m]
  std::vector<double> time_s;         ///< sample times [s], strictly increasing
  std::vector<double> elongation_m;   ///< imposed elongation [m]
  std::vector<double> force_N;        ///< measured force [N]
  size_t rows() const { return time_s.size(); }
};

/// The minimum number of rows of a tension test (a few dozen).
constexpr size_t kMinTensionRows = 36;

/// Reads a tension test: header keys `experiment` (= tension) and `sample_length_m`
/// (in (0, 10] m), columns exactly time_s,elongation_m,force_N. InputError otherwise.
TensionTest readTensionTest(const std::string& path);
/// The same from a stream; `file` names it in messages.
TensionTest parseTensionTest(std::istream& in, const std::string& file);

/// Writes a tension test in the measurement format, with `metadata` as header lines after
/// `experiment` and `sample_length_m` (which it writes itself). Throws std::runtime_error
/// when the file cannot be written.
void writeTensionTest(const std::string& path, const TensionTest& test);

}  // namespace colosim
