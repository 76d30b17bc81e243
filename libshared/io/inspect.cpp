#include "io/inspect.h"

#include <fmt/format.h>

#include <cstdio>

#include "core/error.h"
#include "core/log.h"
#include "core/provenance.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/schema.h"
#include "io/zstd_filter.h"

namespace df::io {
namespace {

std::string shape(const std::vector<std::size_t>& d) {
  std::string s = "[";
  for (std::size_t i = 0; i < d.size(); ++i) s += (i ? "," : "") + std::to_string(d[i]);
  return s + "]";
}

void list_datasets(const h5::File& f, std::string& out) {
  for (const std::string& path : f.descendants()) {
    if (!f.is_dataset(path)) continue;
    h5::DatasetInfo info = f.info(path);
    std::string filters;
    for (int id : info.filters)
      filters += id == h5::kZstdFilterId    ? " zstd"
                 : id == H5Z_FILTER_SHUFFLE ? " shuffle"
                                            : fmt::format(" filter{}", id);
    out += fmt::format("  {:<28} {:<8} {}{}\n", path, h5::dtype_name(info.dtype), shape(info.dims),
                       filters);
  }
}

}  // namespace

int inspect_files(const std::vector<std::string>& files, const InspectOptions& opt) {
  int bad = 0;
  for (const auto& path : files) {
    try {
      h5::File f(path, h5::File::Mode::read);
      ValidationOptions vo;
      vo.check_values = !opt.structure_only;
      Dimensions dims = validate(f, opt.expected_kind, vo);
      std::string kind = declared_kind(f);
      std::string out = fmt::format("{}: OK, {} (schema version {}) written by {} {}\n", path, kind,
                                    f.attr_int("/", "schema_version"), f.attr_string("/", "tool"),
                                    f.attr_string("/", "tool_version"));
      std::string d;
      const auto& doc = schema(kind).doc;
      for (const auto& [name, size] : dims) {
        std::string meaning = doc["dimensions"].contains(name)
                                  ? doc["dimensions"][name].value("description", "")
                                  : "";
        d += fmt::format("  {} = {}{}\n", name, size, meaning.empty() ? "" : "  (" + meaning + ")");
      }
      out += d;
      list_datasets(f, out);
      if (opt.show_history) {
        out += "  history:\n";
        for (const auto& line : provenance::history_lines(read_history(f)))
          out += "    " + line + "\n";
      }
      if (log::enabled(log::Level::info)) std::fputs(out.c_str(), stdout);
      std::fflush(stdout);
    } catch (const Error& e) {
      log::error("{}", e.message());
      ++bad;
    }
  }
  return bad;
}

}  // namespace df::io
