#include "apps/fit_baseline.h"

#include <fmt/format.h>

#include <cmath>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/geodesic_distance.h"
#include "io/acap_file.h"
#include "io/components_file.h"
#include "models/baselines/baselines.h"
#include "models/msae/components.h"
#include "models/msae/data.h"

namespace df::apps {
using namespace df::models;
using Eigen::Index;
using Mat = nn::Matrix<double>;

namespace {

// Stored positions of some frames as rows [n, 3V].
Mat read_positions(const std::string& data, const std::vector<std::int64_t>& frames, Index V) {
  const io::AcapReader in(data);
  if (!in.has_positions())
    throw InvalidInput(
        "has no /frames/positions: SPLOCS works on vertex positions (obj2acap keeps them)", data);
  Mat out(static_cast<Index>(frames.size()), 3 * V);
  std::vector<float> row(static_cast<std::size_t>(3 * V));
  for (std::size_t k = 0; k < frames.size(); ++k) {
    in.read_positions(static_cast<std::size_t>(frames[k]), 1, row.data());
    for (Index j = 0; j < 3 * V; ++j)
      out(static_cast<Index>(k), j) = row[static_cast<std::size_t>(j)];
  }
  return out;
}

// What a linear basis [K, g V] gives a components file of one level, whatever its space: the
// model's template, normalization and history, each component's scale (the training shapes'
// coefficient of largest magnitude, signed, so that a linear basis and an MSAE decode alike),
// centre (its strongest vertex), block 0, kept, and AE₀-style attention masks (eq. 5-6: each
// vertex's share of the components' squared norms there).
io::Components linear_components(const MsaeModel& m, const Mat& basis, const Mat& coefficients,
                                 Index g, const std::string& source, std::vector<double>& scales) {
  const Index K = basis.rows(), V = m.tmpl.vertices.rows();
  io::Components c;
  c.tmpl = m.tmpl;
  c.normalization = m.normalization;
  c.history = m.history;
  c.model = source;
  io::ComponentLevel L;
  L.features.resize(K, g * V);
  scales.clear();
  for (Index k = 0; k < K; ++k) {
    Index top = 0;
    for (Index r = 0; r < coefficients.rows(); ++r)
      if (std::abs(coefficients(r, k)) > std::abs(coefficients(top, k))) top = r;
    scales.push_back(coefficients.rows() ? coefficients(top, k) : 1.0);
    L.center.push_back(static_cast<int>(strongest_vertex(basis.row(k), g)));
    L.block.push_back(0);
    L.code.push_back(scales.back());
    L.kept.push_back(1);
  }
  c.levels.push_back(std::move(L));
  c.attention.resize(K, V);
  for (Index i = 0; i < V; ++i) {
    double sum = 0;
    for (Index k = 0; k < K; ++k) sum += basis.row(k).segment(g * i, g).squaredNorm();
    for (Index k = 0; k < K; ++k)
      c.attention(k, i) =
          sum > 0 ? static_cast<float>(basis.row(k).segment(g * i, g).squaredNorm() / sum) : 0.0f;
  }
  return c;
}

// A basis in normalized ACAP space [K, 9V] as a components file, on the pattern of
// extract-components: component k is the reference's features plus its direction at its scale;
// strength by eq. 7, similarity as Fig. 3's. Every component starts kept.
io::Components basis_components(const MsaeModel& m, const Mat& basis, const Mat& coefficients,
                                const std::string& source) {
  std::vector<double> scale;
  io::Components c = linear_components(m, basis, coefficients, 9, source, scale);
  const int V = static_cast<int>(m.tmpl.vertices.rows());
  const auto ref = geometry::identity_features(&m.normalization);
  auto& L = c.levels[0];
  for (Index k = 0; k < basis.rows(); ++k) {
    for (Index j = 0; j < 9 * static_cast<Index>(V); ++j)
      L.features(k, j) =
          static_cast<float>(ref[static_cast<std::size_t>(j % 9)] + scale[k] * basis(k, j));
    L.strength.push_back(component_strength(L.features.row(k).data(), V, ref, c.eps1));
  }
  c.similarity = level0_similarity(L, ref);
  return c;
}

// SPLOCS' components on positions as a components file of space "positions": each one its
// displacement at its scale, the mean shape beside them; strength: the mean displacement over the
// vertices it moves by more than eps1 (eq. 7 on positions); similarity: |cosine| of the
// displacements.
io::Components position_components(const MsaeModel& m, const Splocs& s, const Mat& coefficients,
                                   const std::string& source) {
  std::vector<double> scale;
  io::Components c = linear_components(m, s.components, coefficients, 3, source, scale);
  const Index K = s.components.rows(), V = m.tmpl.vertices.rows();
  c.space = "positions";
  c.mean = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      s.mean.data(), V, 3);
  auto& L = c.levels[0];
  Mat unit(K, 3 * V);
  for (Index k = 0; k < K; ++k) {
    const Eigen::RowVectorXd d = scale[k] * s.components.row(k);
    L.features.row(k) = d.cast<float>();
    double sum = 0;
    int moved = 0;
    for (Index i = 0; i < V; ++i)
      if (const double n = d.segment(3 * i, 3).norm(); n > c.eps1) sum += n, ++moved;
    L.strength.push_back(moved ? sum / moved : 0.0);
    const double n = s.components.row(k).norm();
    unit.row(k) =
        n > 0 ? Eigen::RowVectorXd(s.components.row(k) / n) : Eigen::RowVectorXd::Zero(3 * V);
  }
  c.similarity = (unit * unit.transpose()).cwiseAbs();
  return c;
}

}  // namespace

void fit_baseline(const BaselineOptions& opt, const CommonOptions& common) {
  const auto claims =
      claim_outputs({opt.output, opt.components_out}, common.force, {opt.model, opt.data});
  const MsaeModel m = load_msae_model(opt.model);
  int k = opt.components;
  if (k == 0)
    for (const auto& b : m.net->blocks()) k += b.kz;
  if (k < 1) throw UsageError("--components must be positive");
  const MsaeShapes train = read_msae_shapes(m, opt.data, FramePart::train);
  const MsaeShapes held = read_msae_shapes(m, opt.data, opt.part);
  if (held.frames.empty())
    throw InvalidInput(fmt::format("the model's {} part is empty", opt.part), opt.model);
  const Index V = m.tmpl.vertices.rows();
  Index fitted = k;  // PCA of fewer shapes than components has fewer
  if (opt.method == BaselineMethod::splocs) {
    SplocsOptions so = opt.splocs;
    so.components = k;
    geometry::GeodesicRows geodesic(m.tmpl.vertices, m.tmpl.faces);
    const Splocs s = fit_splocs(read_positions(opt.data, train.frames, V), so,
                                [&](int i) { return geodesic.row(i); });
    const nn::Matrix<float> recon =
        project_onto(read_positions(opt.data, held.frames, V), s.mean, s.components).cast<float>();
    write_shapes(opt.output, m, held, nullptr, &recon, opt.data, {opt.model, opt.data},
                 common.force, fmt::format("splocs: {} components", k));
    if (!opt.components_out.empty()) {
      const Mat x = read_positions(opt.data, train.frames, V);
      io::write_components(opt.components_out,
                           position_components(m, s, coefficients_on(x, s.mean, s.components),
                                               fmt::format("{} ({})", opt.model, opt.method)),
                           {opt.model, opt.data}, common.force);
    }
  } else {
    // A basis of the normalized ACAP features, reconstructed through acap2obj: PCA's, or SPLOCS'
    // algorithm on 9 numbers per vertex (local linear components in the space MSAE works in).
    const Mat x = train.x.cast<double>();
    Mat mean, basis;
    if (opt.method == BaselineMethod::pca) {
      Pca p = fit_pca(x, k);
      if (p.directions.rows() < k)
        log::warn("PCA of {} training shapes has {} components, not {}", train.frames.size(),
                  p.directions.rows(), k);
      mean = std::move(p.mean), basis = std::move(p.directions);
    } else {
      SplocsOptions so = opt.splocs;
      so.components = k;
      geometry::GeodesicRows geodesic(m.tmpl.vertices, m.tmpl.faces);
      Splocs s = fit_splocs(
          x, so, [&](int i) { return geodesic.row(i); }, 9);
      mean = std::move(s.mean), basis = std::move(s.components);
    }
    fitted = basis.rows();
    const nn::Matrix<float> recon = project_onto(held.x.cast<double>(), mean, basis).cast<float>();
    write_shapes(opt.output, m, held, &recon, nullptr, opt.data, {opt.model, opt.data},
                 common.force, fmt::format("{}: {} components", opt.method, basis.rows()));
    if (!opt.components_out.empty())
      io::write_components(opt.components_out,
                           basis_components(m, basis, coefficients_on(x, mean, basis),
                                            fmt::format("{} ({})", opt.model, opt.method)),
                           {opt.model, opt.data}, common.force);
  }
  log::info("wrote {} {} reconstructions ({} components fitted on {} training shapes) to {}",
            held.frames.size(), opt.method, fitted, train.frames.size(), opt.output);
}

}  // namespace df::apps
