#include "models/common/checkpoint.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/provenance.h"
#include "io/file_header.h"
#include "io/model_file.h"
#include "io/schema.h"

namespace df::models {

void write_training_state(h5::File& f, const nn::ParameterStore<float>& params,
                          const nn::Adam<float>* adam, const Rng& rng, std::int64_t iteration) {
  io::write_iteration(f, iteration);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < params.views().size(); ++i) {
    names.push_back(params.views()[i].name);
    io::write_param(f, names.back(), params.value(static_cast<int>(i)));
  }
  io::write_param_order(f, names);
  if (adam) {
    const auto group = io::model_layout::optimizer();
    io::write_adam_state(
        f, group, std::span<const float>(adam->first_moment().data(), params.size()),
        std::span<const float>(adam->second_moment().data(), params.size()), adam->steps());
    f.set_attr(group, "kind", std::string("adam"));
  }
  io::write_rng_state(f, {rng.state(), rng.has_spare_normal(), rng.spare_normal()});
}

std::int64_t read_training_state(const h5::File& f, nn::ParameterStore<float>& params,
                                 nn::Adam<float>& adam, Rng& rng) {
  const auto names = io::read_param_order(f);
  if (names.size() != params.views().size())
    throw InvalidInput(
        fmt::format("holds {} parameters, the model has {}", names.size(), params.views().size()),
        f.name());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto& v = params.views()[i];
    if (names[i] != v.name)
      throw InvalidInput(
          fmt::format("parameter {} is '{}', the model expects '{}'", i, names[i], v.name),
          f.name());
    params.value(static_cast<int>(i)) = io::read_param(f, v.name, v.rows, v.cols);
  }
  if (has_optimizer_state(f))
    restore_adam(adam, io::read_adam_state(f, io::model_layout::optimizer(), params.size()));
  restore_rng(rng, io::read_rng_state(f));
  return io::read_iteration(f);
}

bool has_optimizer_state(const h5::File& f) {
  return f.exists(io::model_layout::optimizer());
}

void restore_adam(nn::Adam<float>& adam, const io::AdamState& s) {
  adam.first_moment() =
      Eigen::Map<const nn::Vector<float>>(s.m.data(), static_cast<Eigen::Index>(s.m.size()));
  adam.second_moment() =
      Eigen::Map<const nn::Vector<float>>(s.v.data(), static_cast<Eigen::Index>(s.v.size()));
  adam.set_steps(static_cast<long>(s.step));
}

void restore_rng(Rng& rng, const io::RngState& s) {
  rng.restore(s.state, s.has_spare, s.spare);
}

void save_checkpoint(const std::string& path, const nn::ParameterStore<float>& params,
                     const nn::Adam<float>& adam, const Rng& rng, std::int64_t iteration) {
  AtomicOutput out(path, AtomicOutput::Kind::file, true);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "nn-checkpoint");
    write_training_state(f, params, &adam, rng, iteration);
    f.close();
  }
  out.commit();
}

std::int64_t load_checkpoint(const std::string& path, nn::ParameterStore<float>& params,
                             nn::Adam<float>& adam, Rng& rng) {
  h5::File f = io::open_input(path, "nn-checkpoint");
  return read_training_state(f, params, adam, rng);
}

}  // namespace df::models
