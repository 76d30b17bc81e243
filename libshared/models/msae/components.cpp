#include "models/msae/components.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/msae/data.h"
#include "models/msae/diagnosis.h"

namespace df::models {

using Eigen::Index;

std::vector<double> deformation_per_vertex(const float* x, int n_vertices,
                                           const std::array<double, 9>& reference) {
  std::vector<double> out(static_cast<std::size_t>(n_vertices));
  for (int i = 0; i < n_vertices; ++i) {
    double sq = 0;
    for (int d = 0; d < 9; ++d) {
      const double diff =
          static_cast<double>(x[9 * i + d]) - reference[static_cast<std::size_t>(d)];
      sq += diff * diff;
    }
    out[static_cast<std::size_t>(i)] = std::sqrt(sq);
  }
  return out;
}

double component_strength(const float* x, int n_vertices, const std::array<double, 9>& reference,
                          double eps1) {
  double sum = 0;
  int n = 0;
  for (double norm : deformation_per_vertex(x, n_vertices, reference))
    if (norm > eps1) sum += norm, ++n;
  return n ? sum / n : 0.0;
}

std::vector<nn::Matrix<float>> block_codes(const MsaeNet<float>& net, const nn::Matrix<float>& shapes) {
  std::vector<nn::Matrix<float>> codes(net.blocks().size());
  for (Index r = 0; r < shapes.rows(); r += 64) {
    std::vector<nn::Matrix<float>> chunk;
    net.reconstruct(shapes.middleRows(r, std::min<Index>(64, shapes.rows() - r)),
                    net.config().levels(), &chunk);
    for (std::size_t b = 0; b < codes.size(); ++b) {
      codes[b].conservativeResize(codes[b].rows() + chunk[b].rows(), chunk[b].cols());
      codes[b].bottomRows(chunk[b].rows()) = chunk[b];
    }
  }
  return codes;
}

namespace {

// The strength-maximising sign of each component of a block, decoded.
void decode_block(const MsaeNet<float>& net, int b, const nn::Matrix<float>& codes,
                  const std::vector<int>& centres, const std::array<double, 9>& ref, double eps1,
                  ComponentLevel& out) {
  const int kz = net.blocks()[static_cast<std::size_t>(b)].kz, V = net.n_vertices();
  const nn::Matrix<float> zero = net.decode(b, nn::Matrix<float>::Zero(1, kz));
  nn::Matrix<float> z = nn::Matrix<float>::Zero(2 * kz, kz);
  for (int k = 0; k < kz; ++k) {
    z(2 * k, k) = codes.rows() ? codes.col(k).maxCoeff() : 1.0f;
    z(2 * k + 1, k) = codes.rows() ? codes.col(k).minCoeff() : -1.0f;
  }
  nn::Matrix<float> x = net.decode(b, z);
  for (Index r = 0; r < x.rows(); ++r)
    for (Index j = 0; j < x.cols(); ++j)
      x(r, j) += static_cast<float>(ref[static_cast<std::size_t>(j % 9)]) - zero(0, j);
  for (int k = 0; k < kz; ++k) {
    const double plus = component_strength(x.row(2 * k).data(), V, ref, eps1);
    const double minus = component_strength(x.row(2 * k + 1).data(), V, ref, eps1);
    const int pick = minus > plus ? 2 * k + 1 : 2 * k;
    const Index row = out.features.rows();
    out.features.conservativeResize(row + 1, x.cols());
    out.features.row(row) = x.row(pick);
    out.strength.push_back(std::max(plus, minus));
    out.center.push_back(centres[static_cast<std::size_t>(k)]);
    out.block.push_back(b);
    out.code.push_back(static_cast<double>(z(pick, k)));
    out.kept.push_back(1);
  }
}

nn::Matrix<double> level0_similarity(const ComponentLevel& level0,
                                     const std::array<double, 9>& ref) {
  nn::Matrix<double> d = level0.features.cast<double>();
  for (Index j = 0; j < d.cols(); ++j) d.col(j).array() -= ref[static_cast<std::size_t>(j % 9)];
  const Eigen::VectorXd norm = d.rowwise().norm();
  nn::Matrix<double> s = d * d.transpose();
  for (Index a = 0; a < s.rows(); ++a)
    for (Index b = 0; b < s.cols(); ++b) {
      const double n = norm[a] * norm[b];
      s(a, b) = n > 0 ? std::abs(s(a, b)) / n : 0.0;
    }
  return s;
}

}  // namespace

Components extract_components(const MsaeModel& m, const std::vector<nn::Matrix<float>>& codes) {
  const MsaeNet<float>& net = *m.net;
  Components c;
  c.tmpl = m.tmpl;
  c.normalization = m.normalization;
  c.history = m.history;
  const auto ref = geometry::identity_features(&m.normalization);
  c.levels.resize(static_cast<std::size_t>(net.config().levels()));
  const auto centres = net.centres();
  for (std::size_t b = 0; b < net.blocks().size(); ++b)
    decode_block(net, static_cast<int>(b), codes[b], centres[b], ref, c.eps1,
                 c.levels[static_cast<std::size_t>(net.blocks()[b].level)]);
  c.attention = net.attention_masks(0);
  c.similarity = level0_similarity(c.levels[0], ref);
  return c;
}

void prune_components(Components& c, double eps1, double eps2) {
  if (!(eps1 >= 0) || !(eps2 >= 0)) throw UsageError("--eps1 and --eps2 must not be negative");
  const auto ref = geometry::identity_features(&c.normalization);
  const int V = static_cast<int>(c.tmpl.vertices.rows());
  for (auto& level : c.levels)
    for (Index k = 0; k < level.features.rows(); ++k) {
      level.strength[static_cast<std::size_t>(k)] =
          component_strength(level.features.row(k).data(), V, ref, eps1);
      level.kept[static_cast<std::size_t>(k)] =
          level.strength[static_cast<std::size_t>(k)] >= eps2 ? 1 : 0;
    }
  c.eps1 = eps1;
  c.eps2 = eps2;
}

void write_components(const std::string& path, const Components& c,
                      const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "components", {c.history});
    f.set_attr("/", "model", c.model);
    f.set_attr("/", "eps1", c.eps1);
    f.set_attr("/", "eps2", c.eps2);
    io::write_template(f, c.tmpl);
    io::write_normalization(f, c.normalization);
    const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
    for (std::size_t l = 0; l < c.levels.size(); ++l) {
      const auto& L = c.levels[l];
      const std::string g = fmt::format("/level{}", l);
      const auto K = static_cast<std::size_t>(L.features.rows());
      f.write<float>(g + "/features", std::span<const float>(L.features.data(), K * 9 * V),
                     {K, V, 9});
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
  io::Dimensions dims;
  h5::File f = io::open_input(path, "components", &dims);
  Components c;
  c.history = io::read_history(f);
  c.model = f.attr_string("/", "model");
  c.eps1 = f.attr_double("/", "eps1");
  c.eps2 = f.attr_double("/", "eps2");
  c.tmpl = io::read_template(f);
  c.normalization = io::read_normalization(f);
  const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
  for (int l = 0; f.exists(fmt::format("/level{}", l)); ++l) {
    const std::string g = fmt::format("/level{}", l);
    ComponentLevel L;
    auto feats = f.read<float>(g + "/features");
    if (feats.dims.size() != 3 || feats.dims[1] != V)
      throw InvalidInput(fmt::format("components have {} vertices, the template {}",
                                     feats.dims.size() == 3 ? feats.dims[1] : 0, V),
                         f.where(g + "/features"));
    const auto K = static_cast<Index>(feats.dims[0]);
    L.features =
        Eigen::Map<const nn::Matrix<float>>(feats.data.data(), K, static_cast<Index>(9 * V));
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
  c.attention = f.read_matrix<float>("/attention/masks");
  c.similarity = f.read_matrix<double>("/similarity");
  return c;
}

void write_components_acap(const std::string& path, const Components& c, bool kept_only,
                           const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    io::AcapWriter f(out.temp_path(), path, {c.history});
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
        // the component's index within its block
        Index within = 0;
        for (Index j = 0; j < k; ++j)
          within += L.block[static_cast<std::size_t>(j)] == L.block[static_cast<std::size_t>(k)];
        names.push_back(fmt::format("L{}.{}.{}", l, L.block[static_cast<std::size_t>(k)], within));
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

void extract_components_tool(const ExtractOptions& opt, const CommonOptions& common) {
  const MsaeModel m = load_msae_model(opt.model);
  const MsaeShapes train = read_msae_shapes(m, opt.data, "train");
  const auto codes = block_codes(*m.net, train.x);
  Components c = extract_components(m, codes);
  c.model = opt.model;
  write_components(opt.output, c, {opt.model, opt.data}, common.force);
  if (!opt.acap.empty())
    write_components_acap(opt.acap, c, false, {opt.model, opt.data}, common.force);
  std::size_t n = 0;
  for (const auto& L : c.levels) n += static_cast<std::size_t>(L.features.rows());
  log::info("wrote {} components in {} levels to {}{}", n, c.levels.size(), opt.output,
            opt.acap.empty() ? "" : " and " + opt.acap);
  if (!opt.report.empty()) {
    const MsaeShapes held = read_msae_shapes(m, opt.data, opt.report);
    if (held.x.rows() == 0)
      throw InvalidInput(fmt::format("the model's {} part is empty", opt.report), opt.model);
    fmt::print("{}", format_diagnosis(diagnose_msae(m, c, train.x, codes, held.x), opt.report));
  }
}

void prune_components_tool(const PruneOptions& opt, const CommonOptions& common) {
  Components c = read_components(opt.input);
  prune_components(c, opt.eps1, opt.eps2);
  nlohmann::json report = {
      {"eps1", opt.eps1}, {"eps2", opt.eps2}, {"levels", nlohmann::json::array()}};
  fmt::print("level  component  block  centre  strength  kept\n");
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    const auto& L = c.levels[l];
    nlohmann::json level = {{"level", l}, {"components", nlohmann::json::array()}};
    std::size_t kept = 0;
    for (std::size_t k = 0; k < L.strength.size(); ++k) {
      fmt::print("{:>5}  {:>9}  {:>5}  {:>6}  {:>8.4f}  {}\n", l, k, L.block[k], L.center[k],
                 L.strength[k], L.kept[k] ? "yes" : "no");
      level["components"].push_back({{"block", L.block[k]},
                                     {"center", L.center[k]},
                                     {"strength", L.strength[k]},
                                     {"kept", L.kept[k] != 0}});
      kept += L.kept[k];
    }
    level["kept"] = kept;
    level["dropped"] = L.strength.size() - kept;
    fmt::print("level {}: {} kept, {} dropped (strength < {})\n", l, kept, L.strength.size() - kept,
               opt.eps2);
    report["levels"].push_back(level);
  }
  std::size_t kept = 0;
  for (const auto& L : c.levels)
    kept += static_cast<std::size_t>(std::count(L.kept.begin(), L.kept.end(), 1));
  if (!opt.acap.empty() && kept == 0)
    throw InvalidInput(
        fmt::format("no component has strength >= {}: nothing to write to {}", opt.eps2, opt.acap),
        opt.input);
  write_components(opt.output, c, {opt.input}, common.force);
  if (!opt.acap.empty()) write_components_acap(opt.acap, c, true, {opt.input}, common.force);
  if (!opt.json.empty()) {
    AtomicOutput out(opt.json, AtomicOutput::Kind::file, common.force, {opt.input});
    std::ofstream(out.temp_path()) << report.dump(1) << "\n";
    out.commit();
  }
}

}  // namespace df::models
