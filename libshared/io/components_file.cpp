#include "io/components_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <span>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/schema.h"

namespace df::io {

using Eigen::Index;

void write_components(const std::string& path, const Components& c,
                      const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    write_header(f, "components", {c.history});
    f.set_attr("/", "model", c.model);
    f.set_attr("/", "eps1", c.eps1);
    f.set_attr("/", "eps2", c.eps2);
    if (c.space != "acap") f.set_attr("/", "space", c.space);
    if (c.space == "positions") f.write_matrix("/mean", c.mean);
    write_template(f, c.tmpl);
    write_normalization(f, c.normalization);
    const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
    for (std::size_t l = 0; l < c.levels.size(); ++l) {
      const auto& L = c.levels[l];
      const std::string g = fmt::format("/level{}", l);
      const auto K = static_cast<std::size_t>(L.features.rows());
      const auto D = static_cast<std::size_t>(c.per_vertex());
      f.write<float>(g + "/features", std::span<const float>(L.features.data(), K * D * V),
                     {K, V, D});
      f.write<double>(g + "/strength", L.strength, {K});
      f.write<std::int32_t>(g + "/center",
                            std::vector<std::int32_t>(L.center.begin(), L.center.end()), {K});
      f.write<std::int32_t>(g + "/block", std::vector<std::int32_t>(L.block.begin(), L.block.end()),
                            {K});
      f.write<double>(g + "/code", L.code, {K});
      f.write<std::uint8_t>(g + "/kept", L.kept, {K});
    }
    f.write_matrix("/attention/masks", c.attention);
    f.write_matrix("/similarity", c.similarity);
    f.close();
  }
  out.commit();
}

Components read_components(const std::string& path) {
  Dimensions dims;
  h5::File f = open_input(path, "components", &dims);
  Components c;
  c.history = read_history(f);
  c.model = f.attr_string("/", "model");
  c.eps1 = f.attr_double("/", "eps1");
  c.eps2 = f.attr_double("/", "eps2");
  if (f.has_attr("/", "space")) c.space = f.attr_string("/", "space");
  if (c.space != "acap" && c.space != "positions")
    throw InvalidInput(fmt::format("space '{}' is neither acap nor positions", c.space), path);
  c.tmpl = read_template(f);
  c.normalization = read_normalization(f);
  const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
  for (int l = 0; f.exists(fmt::format("/level{}", l)); ++l) {
    const std::string g = fmt::format("/level{}", l);
    ComponentLevel L;
    auto feats = f.read<float>(g + "/features");
    if (feats.dims.size() != 3 || feats.dims[1] != V)
      throw InvalidInput(fmt::format("components have {} vertices, the template {}",
                                     feats.dims.size() == 3 ? feats.dims[1] : 0, V),
                         f.where(g + "/features"));
    const auto D = static_cast<std::size_t>(c.per_vertex());
    if (feats.dims[2] != D)
      throw InvalidInput(
          fmt::format("{} numbers per vertex; {} components have {}", feats.dims[2], c.space, D),
          f.where(g + "/features"));
    const auto K = static_cast<Index>(feats.dims[0]);
    L.features =
        Eigen::Map<const h5::RowMatrix<float>>(feats.data.data(), K, static_cast<Index>(D * V));
    L.strength = f.read<double>(g + "/strength").data;
    for (auto v : f.read<std::int32_t>(g + "/center").data) L.center.push_back(v);
    for (auto v : f.read<std::int32_t>(g + "/block").data) L.block.push_back(v);
    L.code = f.read<double>(g + "/code").data;
    L.kept = f.read<std::uint8_t>(g + "/kept").data;
    const auto k = static_cast<std::size_t>(K);
    if (L.strength.size() != k || L.center.size() != k || L.block.size() != k ||
        L.code.size() != k || L.kept.size() != k)
      throw InvalidInput("the per-component datasets disagree in length", f.where(g));
    c.levels.push_back(std::move(L));
  }
  if (c.levels.empty()) throw InvalidInput("has no /level0", path);
  if (c.space == "positions") {
    c.mean = f.read_matrix<double>("/mean");
    if (c.mean.rows() != c.tmpl.vertices.rows() || c.mean.cols() != 3)
      throw InvalidInput("the mean shape does not match the template", f.where("/mean"));
  }
  c.attention = f.read_matrix<float>("/attention/masks");
  c.similarity = f.read_matrix<double>("/similarity");
  return c;
}

void require_acap_components(const Components& c, const std::string& path,
                             const std::string& what) {
  if (c.space != "acap")
    throw InvalidInput(
        fmt::format("holds {} components (SPLOCS on vertex positions); {} needs ACAP components",
                    c.space, what),
        path);
}

void write_components_acap(const std::string& path, const Components& c, bool kept_only,
                           const std::vector<std::string>& inputs, bool force) {
  require_acap_components(c, c.model, "an acap file of components");
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    AcapWriter f(out.temp_path(), path, {c.history});
    f.write_template(c.tmpl);
    f.write_normalization(c.normalization);
    std::vector<std::string> names, seqs;
    std::vector<std::int64_t> offsets{0};
    std::vector<const float*> rows;
    for (std::size_t l = 0; l < c.levels.size(); ++l) {
      const auto& L = c.levels[l];
      const std::size_t before = rows.size();
      for (Index k = 0; k < L.features.rows(); ++k) {
        if (kept_only && !L.kept[static_cast<std::size_t>(k)]) continue;
        names.push_back(component_name(c, l, static_cast<std::size_t>(k)));
        rows.push_back(L.features.row(k).data());
      }
      if (rows.size() == before) continue;  // a level with nothing kept is left out
      seqs.push_back(fmt::format("level{}", l));
      offsets.push_back(static_cast<std::int64_t>(rows.size()));
    }
    if (rows.empty()) throw InvalidInput("no component is kept: nothing to write", path);
    const auto n = rows.size(), V = static_cast<std::size_t>(c.tmpl.vertices.rows());
    f.write_frame_names(names);
    f.write_sequences(offsets, seqs);
    f.create_normalized(n, V);
    for (std::size_t k = 0; k < n; ++k) f.write_normalized_rows(k, 1, rows[k]);
    f.close();
  }
  out.commit();
}

std::string component_name(const Components& c, std::size_t level, std::size_t k) {
  const auto& block = c.levels.at(level).block;
  const auto within =
      std::count(block.begin(), block.begin() + static_cast<std::ptrdiff_t>(k), block.at(k));
  return fmt::format("L{}.{}.{}", level, block[k], within);
}

bool names_components(const std::vector<std::string>& sequence_names,
                      const std::vector<std::string>& frame_names,
                      const std::vector<std::int64_t>& offsets) {
  if (sequence_names.empty() || offsets.size() != sequence_names.size() + 1 ||
      offsets.back() != static_cast<std::int64_t>(frame_names.size()))
    return false;
  for (std::size_t s = 0; s < sequence_names.size(); ++s) {
    const std::string& q = sequence_names[s];
    if (q.rfind("level", 0) != 0 || q.size() == 5) return false;
    const std::string prefix = "L" + q.substr(5) + ".";
    for (auto f = offsets[s]; f < offsets[s + 1]; ++f)
      if (frame_names[static_cast<std::size_t>(f)].rfind(prefix, 0) != 0) return false;
  }
  return true;
}

}  // namespace df::io
