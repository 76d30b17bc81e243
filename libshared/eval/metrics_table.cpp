#include "eval/metrics_table.h"

#include <fmt/format.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"

namespace df::eval {
namespace {

// Appends the numbers under `j` (a document kept in its file's member order) to `out`.
void flatten(const nlohmann::ordered_json& j, const std::string& prefix,
             std::vector<std::pair<std::string, std::string>>& out) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items())
      flatten(value, prefix.empty() ? key : prefix + "." + key, out);
  } else if (j.is_number_integer() || j.is_number_unsigned()) {
    out.emplace_back(prefix, j.dump());
  } else if (j.is_number_float()) {
    out.emplace_back(prefix, fmt::format("{:.10g}", j.get<double>()));
  }
}

// A number, string or boolean as a cell shows it ("" for anything else).
std::string cell_of(const nlohmann::ordered_json& j) {
  if (j.is_number_integer() || j.is_number_unsigned()) return j.dump();
  if (j.is_number_float()) return fmt::format("{:.10g}", j.get<double>());
  if (j.is_string()) return j.get<std::string>();
  if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
  return "";
}

nlohmann::ordered_json parse_object(const std::string& text, const std::string& where) {
  auto j = nlohmann::ordered_json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InvalidInput("not JSON", where);
  if (!j.is_object())
    throw InvalidInput("not a JSON object (expected eval-metrics --json output)", where);
  return j;
}

std::string value_at(const nlohmann::ordered_json& doc, const std::string& path) {
  const nlohmann::ordered_json* j = &doc;
  std::size_t begin = 0;
  while (begin <= path.size()) {
    const std::size_t dot = std::min(path.find('.', begin), path.size());
    const std::string key = path.substr(begin, dot - begin);
    if (j->is_object()) {
      const auto it = j->find(key);
      if (it == j->end()) return "";
      j = &*it;
    } else if (j->is_array()) {
      std::size_t index = 0;
      const auto [ptr, ec] = std::from_chars(key.data(), key.data() + key.size(), index);
      if (key.empty() || ec != std::errc() || ptr != key.data() + key.size() || index >= j->size())
        return "";
      j = &(*j)[index];
    } else {
      return "";
    }
    begin = dot + 1;
  }
  return cell_of(*j);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError("cannot read the metrics file", path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::string json_value(const std::string& text, const std::string& path, const std::string& where) {
  return value_at(parse_object(text, where), path);
}

std::vector<std::pair<std::string, std::string>> json_numbers(const std::string& text,
                                                              const std::string& where) {
  const auto j = parse_object(text, where);
  std::vector<std::pair<std::string, std::string>> out;
  flatten(j, "", out);
  return out;
}

MetricsTable collect_metrics(const std::vector<std::string>& files,
                             const std::vector<std::string>& names,
                             const std::vector<std::string>& columns, bool require) {
  if (files.empty()) throw UsageError("no metrics files given");
  if (!names.empty() && names.size() != files.size())
    throw UsageError(fmt::format("{} names for {} files", names.size(), files.size()));
  MetricsTable t;
  for (std::size_t i = 0; i < files.size(); ++i) {  // a row per file, named
    const auto dir = std::filesystem::path(files[i]).parent_path().filename().string();
    t.names.push_back(!names.empty() ? names[i] : dir.empty() ? files[i] : dir);
  }
  if (!columns.empty()) {  // the columns asked for, by path
    t.columns = columns;
    for (const auto& file : files) {
      const auto doc = parse_object(read_text(file), file);
      t.cells.emplace_back();
      for (const auto& c : columns) {
        t.cells.back().push_back(value_at(doc, c));
        if (require && t.cells.back().back().empty())
          throw InvalidInput(fmt::format("has no number, string or boolean at '{}'", c), file);
      }
    }
    return t;
  }
  std::map<std::string, std::size_t> column_of;  // every number found, in first-seen order
  std::vector<std::vector<std::pair<std::string, std::string>>> rows;
  for (const auto& file : files) {
    rows.push_back(json_numbers(read_text(file), file));
    for (const auto& [key, value] : rows.back())
      if (column_of.emplace(key, t.columns.size()).second) t.columns.push_back(key);
  }
  for (const auto& row : rows) {
    t.cells.emplace_back(t.columns.size());
    for (const auto& [key, value] : row) t.cells.back()[column_of.at(key)] = value;
  }
  return t;
}

void write_tsv(std::ostream& out, const MetricsTable& table, bool values_only) {
  if (!values_only) {
    out << "name";
    for (const auto& c : table.columns) out << '\t' << c;
    out << '\n';
  }
  for (std::size_t r = 0; r < table.names.size(); ++r) {
    if (!values_only) out << table.names[r];
    for (std::size_t c = 0; c < table.cells[r].size(); ++c)
      out << (c || !values_only ? "\t" : "") << table.cells[r][c];
    out << '\n';
  }
}

}  // namespace df::eval
