// Measurement files (docs/identification.md, "The measurement format"):
//
//   # colosim-measurement v1
//   # experiment: tension
//   # sample_length_m: 0.18
//   # note: any free text
//   time_s,elongation_m,force_N
//   0.000,0.000000,0.0123
//   ...
//
// The reader is generic: every `# key: value` header line is kept as metadata, columns
// are found by name, and the caller says which keys and columns it needs (tension tests in
// identify/tension/tension_test.h, recorded insertions in identify/insertion/recording.h).
// Bad files throw InputError naming the file and line.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <utility>
#include <vector>

namespace colosim {

/// A measurement file as read: header metadata and named numeric columns.
struct Measurement {
  std::string file;                                            ///< path it was read from
  std::vector<std::pair<std::string, std::string>> metadata;  ///< header keys, in file order
  std::vector<std::string> columns;                            ///< column names, in file order
  std::vector<std::vector<double>> values;                     ///< values[column][row]
  int first_data_line = 0;                                     ///< 1-based line of row 0

  size_t rows() const { return values.empty() ? 0 : values[0].size(); }
  bool hasMeta(const std::string& key) const;
  /// The value of a header key; throws InputError naming the file when it is missing.
  const std::string& meta(const std::string& key) const;
  /// A header key read as a finite number in [lo, hi]; InputError otherwise.
  double metaNumber(const std::string& key, double lo, double hi) const;
  /// A column by name; throws InputError when there is none.
  const std::vector<double>& column(const std::string& name) const;
};

/// What a reader requires of a measurement file.
struct MeasurementSpec {
  std::vector<std::string> required_keys;  ///< header keys that must be present
  std::vector<std::string> columns;        ///< the exact column names, in order
  size_t min_rows = 36;                    ///< fewer data rows is an error
};

/// Reads a measurement file: first line `# colosim-measurement v1`, then `# key: value`
/// lines, the column line, and rows of finite numbers. A column named time_s must be
/// strictly increasing. Throws InputError with "file:line: message".
Measurement readMeasurement(const std::string& path, const MeasurementSpec& spec);
/// The same from a stream (readMeasurement opens the file and calls it); `file` names it
/// in messages and in Measurement::file.
Measurement parseMeasurement(std::istream& in, const std::string& file, const MeasurementSpec& spec);

/// The first line of every measurement file.
constexpr const char* kMeasurementFormatLine = "# colosim-measurement v1";

}  // namespace colosim
