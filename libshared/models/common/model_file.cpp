#include "models/common/model_file.h"

#include "io/acap_file.h"
#include "io/model_file.h"

namespace df::models {

void write_mesh_model_common(h5::File& f, const Mesh& tmpl, const geometry::Normalization& nz,
                             const std::vector<double>& log,
                             const std::vector<std::string>& columns,
                             const std::vector<double>& unprinted) {
  io::write_template(f, tmpl);
  io::write_normalization(f, nz);
  io::write_training_log(f, log, columns, unprinted);
}

void read_mesh_model_common(const h5::File& f, Mesh& tmpl, geometry::Normalization& nz,
                            std::vector<double>& log, std::vector<double>& unprinted) {
  tmpl = io::read_template(f);
  nz = io::read_normalization(f);
  auto t = io::read_training_log(f);
  log = std::move(t.rows);
  unprinted = std::move(t.unprinted);
}

}  // namespace df::models
