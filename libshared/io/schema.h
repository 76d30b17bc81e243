// File kinds and their validation. schemas/<kind>.json describes each kind (objects, dtypes,
// ranks with named dimensions, required attributes, value rules); the same JSON is embedded in
// every binary. validate() checks an open file against its kind and reports the first
// violation precisely: wrong kind, missing dataset, wrong rank/shape, a dimension (V, N, ...)
// that differs between two datasets, NaN/Inf, an index out of range, broken offsets.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "io/h5.h"

namespace df::io {

/// Generated at build time from schemas/*.json: kind -> JSON text.
const std::map<std::string, std::string_view>& embedded_schemas();

/// Root attributes every deformflow HDF5 file carries.
inline const std::vector<std::string> kCommonRootAttributes = {"schema", "schema_version", "tool",
                                                               "tool_version", "history"};

struct Schema {
  std::string kind;
  int version = 0;
  nlohmann::json doc;
};

/// The embedded schema of a kind; throws InvalidInput for an unknown kind.
const Schema& schema(const std::string& kind);
std::vector<std::string> schema_kinds();

/// Sizes of the named dimensions found while validating (e.g. {"N": 204, "V": 2904, ...}).
using Dimensions = std::map<std::string, std::size_t>;

struct ValidationOptions {
  /// Also read the data: NaN/Inf, index ranges, offsets (structure only when false).
  bool check_values = true;
  /// Datasets larger than this are not scanned for NaN/Inf here; a tool that reads them
  /// checks as it reads (check_finite_rows), so a huge input is not decompressed twice.
  std::size_t max_finite_scan_bytes = SIZE_MAX;
};

/// What tools use when opening inputs: full structure and index checks, NaN scans of
/// datasets up to 64 MiB.
ValidationOptions tool_validation();

/// Throws InvalidInput naming the first NaN/Inf among `count` rows of `row_size` values that
/// start at row `first` of `dataset` in `file`.
template <class T>
void check_finite_rows(const T* data, std::size_t first, std::size_t count, std::size_t row_size,
                       const std::string& where);

/// Validates `f` against the schema of `expected_kind`, or of the kind the file declares when
/// expected_kind is empty. Returns the dimension sizes; throws InvalidInput on the first
/// violation, naming the file and object.
Dimensions validate(const h5::File& f, const std::string& expected_kind = {},
                    const ValidationOptions& opt = {});

/// The kind a file declares in its `schema` attribute; InvalidInput if it has none.
std::string declared_kind(const h5::File& f);

/// Opens an input file read-only and validates it as `kind` (what every tool does on open).
h5::File open_input(const std::string& path, const std::string& kind, Dimensions* dims = nullptr,
                    const ValidationOptions& opt = tool_validation());

/// Throws InvalidInput if dimension `name` differs between two validated inputs.
void require_same_dimension(const std::string& name, const Dimensions& a, const std::string& file_a,
                            const Dimensions& b, const std::string& file_b);

}  // namespace df::io
