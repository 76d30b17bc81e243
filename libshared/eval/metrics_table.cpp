#include "eval/metrics_table.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_output.h"
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

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError("cannot read the metrics file", path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::vector<std::pair<std::string, std::string>> json_numbers(const std::string& text,
                                                              const std::string& where) {
  const auto j = nlohmann::ordered_json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InvalidInput("not JSON", where);
  if (!j.is_object())
    throw InvalidInput("not a JSON object (expected eval-metrics --json output)", where);
  std::vector<std::pair<std::string, std::string>> out;
  flatten(j, "", out);
  return out;
}

MetricsTable collect_metrics(const std::vector<std::string>& files,
                             const std::vector<std::string>& names) {
  if (files.empty()) throw UsageError("no metrics files given");
  if (!names.empty() && names.size() != files.size())
    throw UsageError(fmt::format("{} names for {} files", names.size(), files.size()));
  MetricsTable t;
  std::map<std::string, std::size_t> column_of;
  std::vector<std::vector<std::pair<std::string, std::string>>> rows;
  for (std::size_t i = 0; i < files.size(); ++i) {
    rows.push_back(json_numbers(read_text(files[i]), files[i]));
    for (const auto& [key, value] : rows.back())
      if (column_of.emplace(key, t.columns.size()).second) t.columns.push_back(key);
    const auto dir = std::filesystem::path(files[i]).parent_path().filename().string();
    t.names.push_back(!names.empty() ? names[i] : dir.empty() ? files[i] : dir);
  }
  for (const auto& row : rows) {
    t.cells.emplace_back(t.columns.size());
    for (const auto& [key, value] : row) t.cells.back()[column_of.at(key)] = value;
  }
  return t;
}

void write_tsv(std::ostream& out, const MetricsTable& table) {
  out << "name";
  for (const auto& c : table.columns) out << '\t' << c;
  out << '\n';
  for (std::size_t r = 0; r < table.names.size(); ++r) {
    out << table.names[r];
    for (const auto& cell : table.cells[r]) out << '\t' << cell;
    out << '\n';
  }
}

void collect_metrics_tool(const CollectMetricsOptions& opt) {
  const MetricsTable table = collect_metrics(opt.files, opt.names);
  if (opt.output.empty() || opt.output == "-") {
    write_tsv(std::cout, table);
    return;
  }
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, opt.force,
                   {opt.files.begin(), opt.files.end()});
  {
    std::ofstream f(out.temp_path());
    write_tsv(f, table);
    if (!f) throw IOError("cannot write the table", opt.output);
  }
  out.commit();
}

}  // namespace df::eval
