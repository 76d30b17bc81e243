#include "io/model_file.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/provenance.h"

namespace df::io {

namespace model_layout {
std::string split_part(const std::string& part) {
  return std::string(split) + "/" + part;
}
std::string geodesic_part(const std::string& name) {
  return std::string(geodesic) + "/" + name;
}
std::string param(const std::string& name) {
  return std::string(params) + "/" + name;
}
std::string optimizer(const std::string& name) {
  return name.empty() ? "/optimizer" : "/optimizers/" + name;
}
}  // namespace model_layout

void write_iteration(h5::File& f, std::int64_t iteration) {
  f.set_attr("/", "iteration", iteration);
}
std::int64_t read_iteration(const h5::File& f) {
  return f.attr_int("/", "iteration");
}

void write_param_order(h5::File& f, const std::vector<std::string>& names) {
  std::string order;
  for (const auto& n : names) order += n + "\n";
  f.set_attr(model_layout::params, "order", order);
}

std::vector<std::string> read_param_order(const h5::File& f) {
  return provenance::history_lines(f.attr_string(model_layout::params, "order"));
}

h5::RowMatrix<float> read_param(const h5::File& f, const std::string& name, Eigen::Index rows,
                                Eigen::Index cols) {
  const auto path = model_layout::param(name);
  auto m = f.read_matrix<float>(path);
  if (m.rows() != rows || m.cols() != cols)
    throw InvalidInput(fmt::format("parameter '{}' is [{},{}], the model expects [{},{}]", name,
                                   m.rows(), m.cols(), rows, cols),
                       f.where(path));
  return m;
}

void write_adam_state(h5::File& f, const std::string& group, std::span<const float> m,
                      std::span<const float> v, std::int64_t step) {
  f.create_groups(group);
  f.set_attr(group, "step", step);
  f.write<float>(group + "/m", m, {m.size()});
  f.write<float>(group + "/v", v, {v.size()});
}

AdamState read_adam_state(const h5::File& f, const std::string& group, std::size_t size) {
  AdamState s;
  s.m = f.read<float>(group + "/m").data;
  s.v = f.read<float>(group + "/v").data;
  if (s.m.size() != size || s.v.size() != size)
    throw InvalidInput("optimizer state does not match the parameters", f.where(group));
  s.step = f.attr_int(group, "step");
  return s;
}

void write_rng_state(h5::File& f, const RngState& s) {
  f.write<std::uint64_t>("/rng/state",
                         std::span<const std::uint64_t>(s.state.data(), s.state.size()), {4});
  f.set_attr(model_layout::rng, "has_spare", static_cast<std::int64_t>(s.has_spare));
  f.set_attr(model_layout::rng, "spare", s.spare);
}

RngState read_rng_state(const h5::File& f) {
  const auto st = f.read<std::uint64_t>("/rng/state").data;
  if (st.size() != 4) throw InvalidInput("the RNG state is not 4 numbers", f.where("/rng/state"));
  RngState s;
  std::copy(st.begin(), st.end(), s.state.begin());
  s.has_spare = f.attr_int(model_layout::rng, "has_spare") != 0;
  s.spare = f.attr_double(model_layout::rng, "spare");
  return s;
}

void write_training_log(h5::File& f, const std::vector<double>& log,
                        const std::vector<std::string>& columns,
                        const std::vector<double>& unprinted) {
  if (!unprinted.empty()) f.write<double>("/training/unprinted", unprinted, {unprinted.size()});
  if (log.empty()) return;
  f.write<double>(model_layout::training_log, log, {log.size() / columns.size(), columns.size()});
  std::string names;
  for (const auto& n : columns) names += (names.empty() ? "" : " ") + n;
  f.set_attr(model_layout::training_log, "columns", names);
}

TrainingLog read_training_log(const h5::File& f) {
  TrainingLog t;
  if (f.exists(model_layout::training_log)) {
    t.rows = f.read<double>(model_layout::training_log).data;
    t.columns = f.attr_string(model_layout::training_log, "columns");
  }
  if (f.exists("/training/unprinted")) t.unprinted = f.read<double>("/training/unprinted").data;
  return t;
}

}  // namespace df::io
