// One table from many metrics files: the JSON that eval-metrics --json (or any tool) wrote for
// each run of a sweep, one row per file, one column per number found in them.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace df::eval {

struct MetricsTable {
  std::vector<std::string> columns;             ///< dotted paths: "E_rms", "sted.spatial", ...
  std::vector<std::string> names;               ///< one per row
  std::vector<std::vector<std::string>> cells;  ///< [row][column]; "" where a file lacks it
};

/// The numbers of a JSON document as (dotted path, printed value) in document order: members
/// of objects recursively; arrays (per-step lists) and strings are left out.
std::vector<std::pair<std::string, std::string>> json_numbers(const std::string& text,
                                                              const std::string& where);

/// The value at a dotted path of a JSON document: object members by name, array elements by
/// their index ("levels.1.kept"), printed as the table prints numbers (strings as they are,
/// true/false); "" if the document has no number, string or boolean there.
std::string json_value(const std::string& text, const std::string& path, const std::string& where);

/// Reads each file; a row is named by names[i], or when names is empty by the file's directory
/// (sweep/kz10/metrics.json -> kz10). Columns are the union in first-seen order, or `columns`
/// when given (json_value's paths, array elements and strings included).
/// @throws IOError for an unreadable file, InvalidInput for one that is not a JSON object;
///         with `require`, InvalidInput naming the file and path for a value a file lacks
MetricsTable collect_metrics(const std::vector<std::string>& files,
                             const std::vector<std::string>& names,
                             const std::vector<std::string>& columns = {}, bool require = false);

/// Tab-separated: a header "name<TAB>columns...", then one line per row; `values_only`: the
/// cells alone (what a script reads).
void write_tsv(std::ostream& out, const MetricsTable& table, bool values_only = false);

}  // namespace df::eval
