#include "io/file_header.h"

#include "core/log.h"
#include "core/provenance.h"
#include "io/schema.h"

namespace df::io {

void write_header(h5::File& f, const std::string& kind, const std::vector<std::string>& inherited) {
  const Schema& s = schema(kind);
  f.set_attr("/", "schema", kind);
  f.set_attr("/", "schema_version", static_cast<std::int64_t>(s.version));
  f.set_attr("/", "tool", log::program());
  f.set_attr("/", "tool_version", std::string(DEFORMFLOW_VERSION));
  f.set_attr("/", "history", provenance::history(inherited));
}

std::string read_history(const h5::File& f) {
  return f.has_attr("/", "history") ? f.attr_string("/", "history") : std::string();
}

}  // namespace df::io
