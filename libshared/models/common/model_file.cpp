#include "models/common/model_file.h"

namespace df::models {

void write_mesh_model_common(h5::File& f, const io::Mesh& tmpl, const geometry::Normalization& nz,
                             const std::vector<double>& log,
                             const std::vector<std::string>& columns,
                             const std::vector<double>& unprinted) {
  io::write_template(f, tmpl);
  io::write_normalization(f, nz);
  if (!unprinted.empty()) f.write<double>("/training/unprinted", unprinted, {unprinted.size()});
  if (log.empty()) return;
  f.write<double>("/training/log", log, {log.size() / columns.size(), columns.size()});
  std::string names;
  for (const auto& n : columns) names += (names.empty() ? "" : " ") + n;
  f.set_attr("/training/log", "columns", names);
}

void read_mesh_model_common(const h5::File& f, io::Mesh& tmpl, geometry::Normalization& nz,
                            std::vector<double>& log, std::vector<double>& unprinted) {
  tmpl = io::read_template(f);
  nz = io::read_normalization(f);
  log = f.exists("/training/log") ? f.read<double>("/training/log").data : std::vector<double>{};
  unprinted = f.exists("/training/unprinted") ? f.read<double>("/training/unprinted").data
                                              : std::vector<double>{};
}

}  // namespace df::models
