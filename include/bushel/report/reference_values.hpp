#pragma once
// Measured or published values that a run's results are set against in `bushel report`: a CSV
// with the columns scenario, result, value, unit, sd and source, and any number of parameter
// columns that a run must match (data/reference_values.csv, built in, holds the reference
// wheat study's values).

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bushel/scenario/run_summary.hpp"
#include "bushel/units/units.hpp"

namespace bushel {

struct ReferenceValue {
  std::string scenario;  ///< the scenario's name (file stem) it applies to; empty: any
  std::string result;    ///< the result it stands beside
  /// Parameters a run must have, with their values as written ("large", "5.1 cm").
  std::vector<std::pair<std::string, std::string>> conditions;
  double value = 0.0;  ///< [SI; radians for angles]
  units::Dimension dimension;
  std::optional<double> sd;  ///< its standard deviation where the source gives one [as value]
  std::string source;        ///< where it comes from ("lab (study; 10 replicates)")
  std::string origin;        ///< "file:line", for messages
};

/// Parses a reference table; `source` names it in errors. Throws InputError (file, line,
/// column) for a missing column, an empty result, source or value, or a value with a bad unit,
/// or a standard deviation (optional column sd, in the value's unit) that is negative or not a number.
std::vector<ReferenceValue> parse_reference_values(std::string_view text, const std::string& source);

/// Reads a reference table from a file.
std::vector<ReferenceValue> read_reference_values(const std::string& path);

/// The built-in table (data/reference_values.csv): the reference wheat study's measurements.
const std::vector<ReferenceValue>& study_reference_values();

/// True if the reference is for this run: the same scenario (when it names one) and every
/// condition met by the run's parameter, as quantities when both parse (5.1cm = 51 mm),
/// else as text (case-insensitive).
bool reference_applies(const ReferenceValue& reference, const RunSummary& run);

/// The reference's value in the unit of `result` (SI, degrees for angles); throws InputError
/// naming the reference's origin if the result's unit is of another kind.
double reference_in_unit_of(const ReferenceValue& reference, const RunResult& result);

}  // namespace bushel
