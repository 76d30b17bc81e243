#include "nn/checkpoint.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/provenance.h"
#include "io/file_header.h"
#include "io/schema.h"

namespace df::nn {

void write_training_state(h5::File& f, const ParameterStore<float>& params, const Adam<float>& adam, const Rng& rng,
                          std::int64_t iteration) {
  f.set_attr("/", "iteration", iteration);
  std::string order;
  for (std::size_t i = 0; i < params.views().size(); ++i) {
    const auto& v = params.views()[i];
    f.write_matrix("/params/" + v.name, params.value(static_cast<int>(i)));
    order += v.name + "\n";
  }
  f.set_attr("/params", "order", order);
  f.create_groups("/optimizer");
  f.set_attr("/optimizer", "kind", std::string("adam"));
  f.set_attr("/optimizer", "step", static_cast<std::int64_t>(adam.steps()));
  f.write<float>("/optimizer/m", std::span<const float>(adam.first_moment().data(), params.size()), {params.size()});
  f.write<float>("/optimizer/v", std::span<const float>(adam.second_moment().data(), params.size()), {params.size()});
  auto st = rng.state();
  f.write<std::uint64_t>("/rng/state", std::span<const std::uint64_t>(st.data(), st.size()), {4});
  f.set_attr("/rng", "has_spare", static_cast<std::int64_t>(rng.has_spare_normal()));
  f.set_attr("/rng", "spare", rng.spare_normal());
}

std::int64_t read_training_state(const h5::File& f, ParameterStore<float>& params, Adam<float>& adam, Rng& rng) {
  auto names = provenance::history_lines(f.attr_string("/params", "order"));
  if (names.size() != params.views().size())
    throw InvalidInput(fmt::format("holds {} parameters, the model has {}", names.size(), params.views().size()),
                       f.name());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto& v = params.views()[i];
    if (names[i] != v.name)
      throw InvalidInput(fmt::format("parameter {} is '{}', the model expects '{}'", i, names[i], v.name), f.name());
    auto m = f.read_matrix<float>("/params/" + v.name);
    if (m.rows() != v.rows || m.cols() != v.cols)
      throw InvalidInput(fmt::format("parameter '{}' is [{},{}], the model expects [{},{}]", v.name, m.rows(), m.cols(),
                                     v.rows, v.cols),
                         f.where("/params/" + v.name));
    params.value(static_cast<int>(i)) = m;
  }
  auto m = f.read<float>("/optimizer/m").data, v = f.read<float>("/optimizer/v").data;
  if (m.size() != params.size() || v.size() != params.size())
    throw InvalidInput("optimizer state does not match the parameters", f.where("/optimizer"));
  adam.first_moment() = Eigen::Map<const Vector<float>>(m.data(), static_cast<Eigen::Index>(m.size()));
  adam.second_moment() = Eigen::Map<const Vector<float>>(v.data(), static_cast<Eigen::Index>(v.size()));
  adam.set_steps(static_cast<long>(f.attr_int("/optimizer", "step")));
  auto s = f.read<std::uint64_t>("/rng/state").data;
  rng.restore({s[0], s[1], s[2], s[3]}, f.attr_int("/rng", "has_spare") != 0, f.attr_double("/rng", "spare"));
  return f.attr_int("/", "iteration");
}

void save_checkpoint(const std::string& path, const ParameterStore<float>& params, const Adam<float>& adam,
                     const Rng& rng, std::int64_t iteration) {
  AtomicOutput out(path, AtomicOutput::Kind::file, true);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "nn-checkpoint");
    write_training_state(f, params, adam, rng, iteration);
    f.close();
  }
  out.commit();
}

std::int64_t load_checkpoint(const std::string& path, ParameterStore<float>& params, Adam<float>& adam, Rng& rng) {
  h5::File f = io::open_input(path, "nn-checkpoint");
  return read_training_state(f, params, adam, rng);
}

}  // namespace df::nn
