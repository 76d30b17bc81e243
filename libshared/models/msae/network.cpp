#include "models/msae/network.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/error.h"
#include "core/rng.h"
#include "nn/adam.h"
#include "nn/ops.h"

namespace df::models {

using Eigen::Index;

template <class T>
MsaeNet<T>::MsaeNet(const MsaeConfig& config, int n_vertices,
                    const std::vector<std::array<int, 2>>& edges, std::uint64_t seed)
    : config_(config), n_vertices_(n_vertices) {
  if (config_.kz.empty() || config_.kz.size() != config_.d.size())
    throw UsageError("--kz and --d need one value per level");
  for (int k : config_.kz)
    if (k < 1) throw UsageError("--kz values must be positive");
  if (config_.attention_sharpness != 1 && config_.attention_sharpness != 2 &&
      config_.attention_sharpness != 4)
    throw UsageError(fmt::format("--attention-sharpness must be 1, 2 or 4 (got {})",
                                 config_.attention_sharpness));
  if (!(config_.centre_separation >= 0 && config_.centre_separation <= 4))
    throw UsageError("--centre-separation must be between 0 and 4 (a fraction of d)");
  if (!(config_.lambda_whole >= 0)) throw UsageError("--lambda-whole must not be negative");
  adjacency_ = nn::neighbour_mean_operator<T>(n_vertices, edges);
  Rng rng(seed, 0);
  // The tree, level by level: with attention every block has kz children; without, one block
  // per level with as many components as the attention tree has there.
  int width = 1;  // blocks of the attention tree at this level
  for (int l = 0; l < config_.levels(); ++l) {
    level_begin_.push_back(static_cast<int>(blocks_.size()));
    const int kz = config_.kz[static_cast<std::size_t>(l)];
    const int n_blocks = config_.attention ? width : 1;
    for (int k = 0; k < n_blocks; ++k) {
      Block b;
      b.level = l;
      b.kz = config_.attention ? kz : kz * width;
      if (l > 0) {
        const int first_parent = level_begin_[static_cast<std::size_t>(l - 1)];
        b.parent = config_.attention
                       ? first_parent + k / config_.kz[static_cast<std::size_t>(l - 1)]
                       : first_parent;
        b.slot = config_.attention ? k % config_.kz[static_cast<std::size_t>(l - 1)] : 0;
        blocks_[static_cast<std::size_t>(b.parent)].children.push_back(
            static_cast<int>(blocks_.size()));
      }
      const std::string name = fmt::format("ae{}.{}", l, k);
      b.conv = nn::MeshConv<T>(store_, name + ".conv", 9, 9, adjacency_, rng);
      b.c = store_.add(name + ".C", b.kz, 9 * Index{n_vertices});
      store_.glorot_uniform(b.c, rng);
      if (config_.init ==
          MsaeInit::normal)  // drawn after Glorot's, so "glorot" models keep their weights
        for (int w : {b.conv.w_point, b.conv.w_nb, b.c}) store_.normal(w, rng, 0.02);
      if (config_.init == MsaeInit::small) store_.value(b.c) *= T(0.01);
      b.b_dec = store_.add(name + ".decoder_bias", 1, 9);
      blocks_.push_back(std::move(b));
    }
    width *= kz;
  }
  level_begin_.push_back(static_cast<int>(blocks_.size()));
  // Added last, so that the blocks' weights are drawn as without it.
  if (config_.centre_features) offset_ = store_.add("offset", 1, 9 * Index{n_vertices});
}

template <class T>
void MsaeNet<T>::set_offset(const Matrix& mean) {
  if (offset_ < 0) throw Error("internal: set_offset needs centre_features");
  if (mean.rows() != 1 || mean.cols() != frame_size())
    throw Error("internal: set_offset needs [1, 9V]");
  store_.value(offset_) = mean;
}

template <class T>
void MsaeNet<T>::start_block(int b, const Matrix& components, double scale) {
  const Block& bl = blocks_.at(static_cast<std::size_t>(b));
  if (components.rows() != bl.kz || components.cols() != frame_size())
    throw Error("internal: start_block needs [K_z, 9V]");
  if (!(scale > 0)) throw Error("internal: start_block needs a positive scale");
  store_.value(bl.c) = components / static_cast<T>(scale);
  store_.value(bl.conv.w_point).setIdentity();
  store_.value(bl.conv.w_point) *= static_cast<T>(scale);
  store_.value(bl.conv.w_nb).setZero();
  store_.value(bl.conv.b).setZero();
  store_.value(bl.b_dec).setZero();
}

template <class T>
std::vector<int> MsaeNet<T>::level_parameters(int level) const {
  std::vector<int> out;
  for (const Block& b : blocks_)
    if (b.level == level) {
      const auto p = b.parameters();
      out.insert(out.end(), p.begin(), p.end());
    }
  return out;
}

template <class T>
nn::Bound<T> MsaeNet<T>::bind_block(nn::Tape<T>& tape, int b, bool variables) const {
  nn::Bound<T> p;
  p.vars.resize(store_.views().size());
  for (int k : blocks_[static_cast<std::size_t>(b)].parameters())
    p.vars[static_cast<std::size_t>(k)] =
        variables ? tape.variable(store_.value(k)) : tape.constant(store_.value(k));
  return p;
}

template <class T>
nn::Var<T> MsaeNet<T>::decoder(const nn::Bound<T>& p, int b, Var z) const {
  const Block& bl = blocks_[static_cast<std::size_t>(b)];
  Var y = nn::matmul(z, p[bl.c]);
  if (config_.decoder_fc == MsaeActivation::tanh) y = nn::tanh(y);
  Var out = nn::tanh(
      config_.decoder_conv == DecoderConv::shared
          ? nn::mesh_conv(y, p[bl.conv.w_point], p[bl.conv.w_nb], p[bl.b_dec], bl.conv.adjacency)
          : bl.conv.tied_transpose(p, y, p[bl.b_dec]));
  // The offset is a constant of the tape: it never receives a gradient, so Adam leaves it.
  if (b == 0 && offset_ >= 0) out = nn::add(out, z.tape->constant(store_.value(offset_)));
  return out;
}

template <class T>
std::vector<std::vector<int>> MsaeNet<T>::centres() const {
  std::vector<std::vector<int>> out;
  for (const Block& b : blocks_) {
    auto C = store_.value(b.c);
    std::vector<int> c(static_cast<std::size_t>(b.kz));
    for (int k = 0; k < b.kz; ++k) {
      T best = -1;
      for (int i = 0; i < n_vertices_; ++i) {
        const T norm = C.row(k).segment(9 * Index{i}, 9).squaredNorm();
        if (norm > best) best = norm, c[static_cast<std::size_t>(k)] = i;
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

template <class T>
void MsaeNet<T>::project_onto_support(const std::vector<Matrix>& lambda) {
  if (lambda.size() != blocks_.size())
    throw Error("internal: project_onto_support needs every block");
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    auto C = store_.value(blocks_[b].c);
    for (int k = 0; k < blocks_[b].kz; ++k)
      for (int i = 0; i < n_vertices_; ++i)
        if (lambda[b](k, i) != T(0)) C.row(k).segment(9 * Index{i}, 9).setZero();
  }
}

template <class T>
void MsaeNet<T>::proximal_sparsity(const std::vector<Matrix>& lambda,
                                   const typename nn::Adam<T>::StepSizes& eta,
                                   const std::vector<int>& levels) {
  if (lambda.size() != blocks_.size()) throw Error("internal: proximal_sparsity needs every block");
  if (!eta.v || eta.v->size() != static_cast<Index>(store_.size()))
    throw Error("internal: proximal_sparsity needs the optimizer of this model");
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Block& bl = blocks_[b];
    if (!levels.empty() && std::find(levels.begin(), levels.end(), bl.level) == levels.end())
      continue;
    auto C = store_.value(bl.c);
    const Index base = store_.views()[static_cast<std::size_t>(bl.c)].offset;
    const T weight = static_cast<T>(config_.lambda_sparse) / static_cast<T>(bl.kz);
    const T cap = static_cast<T>(config_.proximal_cap);
    tbb::parallel_for(0, bl.kz, [&](int k) {
      // The row's rates at once (eta(j) would search the rate ranges for each coordinate).
      const Index row = base + Index{k} * C.cols();
      std::vector<T> rates(static_cast<std::size_t>(C.cols()));
      eta.rates_of(row, C.cols(), rates.data());
      for (int i = 0; i < n_vertices_; ++i) {
        const T mask = lambda[b](k, i);
        if (mask == T(0)) continue;
        auto group = C.row(k).segment(9 * Index{i}, 9);
        const Index first = row + 9 * Index{i};
        T mean_step = 0, mean_rate = 0;
        for (Index j = 0; j < 9; ++j) {  // as eta(first + j) and eta.rate_of(first + j)
          const T rate = rates[static_cast<std::size_t>(first - row + j)];
          mean_step += eta.at_rate(first + j, rate);
          mean_rate += rate;
        }
        T tau = mean_step / T(9) * weight * mask;
        if (cap > 0) tau = std::min(tau, cap * mean_rate / T(9) * mask);
        const T norm = group.norm();
        if (norm <= tau)
          group.setZero();
        else
          group *= (norm - tau) / norm;
      }
    });
  }
}

template <class T>
void MsaeNet<T>::place_centres(const std::vector<std::vector<int>>& vertices) {
  if (vertices.size() != blocks_.size()) throw Error("internal: place_centres needs every block");
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    auto C = store_.value(blocks_[b].c);
    for (int k = 0; k < blocks_[b].kz; ++k) {
      T top = 0;
      for (int i = 0; i < n_vertices_; ++i)
        top = std::max(top, C.row(k).segment(9 * Index{i}, 9).norm());
      auto group = C.row(k).segment(9 * Index{vertices[b].at(static_cast<std::size_t>(k))}, 9);
      const T norm = group.norm();
      if (norm > 0)
        group *= 2 * top / norm;
      else
        group.setConstant(2 * top / 3);
    }
  }
}

template <class T>
nn::Var<T> MsaeNet<T>::masks_of(const nn::Bound<T>& p, int b) const {
  nn::Var<T> am = nn::square(nn::group_norm(p[blocks_[static_cast<std::size_t>(b)].c], Index{9}));
  for (int q = 1; q < config_.attention_sharpness; q *= 2) am = nn::square(am);  // am^p
  // A vertex no component touches would divide 0 by 0; the tiny floor keeps it finite.
  return nn::div(am, nn::add_scalar(nn::sum_rows(am), T(1e-20)));
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::attention_masks(int block) const {
  nn::Tape<T> tape;
  return masks_of(bind_block(tape, block, false), block).value();
}

template <class T>
typename MsaeNet<T>::BlockOutput MsaeNet<T>::forward_block(const nn::Bound<T>& p, int b, Var x,
                                                           const Matrix* lambda, Var* loss,
                                                           MsaeLossTerms* terms,
                                                           const Matrix* weights) const {
  const Block& bl = blocks_[static_cast<std::size_t>(b)];
  Var C = p[bl.c];
  const Var in = b == 0 && offset_ >= 0 ? nn::sub(x, x.tape->constant(store_.value(offset_))) : x;
  Var h = nn::tanh(bl.conv(p, in));
  Var z = nn::matmul_transposed(h, C);
  if (config_.latent == MsaeActivation::tanh) z = nn::tanh(z);
  BlockOutput out;
  out.z = z;
  out.xhat = decoder(p, b, z);
  out.residual = nn::sub(x, out.xhat);
  if (config_.attention && !bl.children.empty()) out.masks = masks_of(p, b);
  if (loss) {
    nn::Tape<T>& tape = *x.tape;
    const T inv_kz = T(1) / static_cast<T>(bl.kz);
    Var recon = weights ? nn::scale(nn::sum_squares(out.residual, weights), T(1) / weights->sum())
                        : nn::scale(nn::sum_squares(out.residual), T(1) / static_cast<T>(x.rows()));
    Var omega =
        nn::scale(nn::sum(nn::mul(nn::group_norm(C, Index{9}), tape.constant(*lambda))), inv_kz);
    Var vz = nn::mean(
        nn::relu(nn::add_scalar(nn::max_rows(nn::abs(z)), static_cast<T>(-config_.theta))));
    // With --support proximal Ω stays out of the gradient: its proximal step follows the
    // optimizer's (proximal_sparsity). The reported total includes it either way.
    const bool proximal = config_.support == Support::proximal;
    Var fit = nn::scale(recon, static_cast<T>(config_.lambda_recon));
    Var l =
        proximal
            ? nn::add(fit, vz)
            : nn::add(nn::add(fit, nn::scale(omega, static_cast<T>(config_.lambda_sparse))), vz);
    *loss = loss->id < 0 ? l : nn::add(*loss, l);
    if (terms) {
      terms->total +=
          static_cast<double>(l.value()(0, 0)) +
          (proximal ? config_.lambda_sparse * static_cast<double>(omega.value()(0, 0)) : 0.0);
      terms->recon += static_cast<double>(recon.value()(0, 0));
      terms->sparsity += static_cast<double>(omega.value()(0, 0));
      terms->latent += static_cast<double>(vz.value()(0, 0));
    }
  }
  return out;
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::child_input(const Block& child, const Matrix& residual,
                                                    const Matrix* masks) const {
  if (!masks) return residual;
  Matrix in(residual.rows(), residual.cols());
  tbb::parallel_for(Index{0}, residual.rows(), [&](Index r) {
    for (Index i = 0; i < n_vertices_; ++i)
      in.row(r).segment(9 * i, 9) = residual.row(r).segment(9 * i, 9) * (*masks)(child.slot, i);
  });
  return in;
}

namespace {
// Which levels contribute to the loss (all when `levels` is empty) and the deepest one.
std::vector<char> training_levels(int n_levels, const std::vector<int>& levels, int& deepest) {
  std::vector<char> trains(static_cast<std::size_t>(n_levels), levels.empty() ? 1 : 0);
  for (int l : levels) {
    if (l < 0 || l >= n_levels) throw Error(fmt::format("internal: no level {}", l));
    trains[static_cast<std::size_t>(l)] = 1;
  }
  deepest = -1;
  for (int l = 0; l < n_levels; ++l)
    if (trains[static_cast<std::size_t>(l)]) deepest = l;
  return trains;
}
}  // namespace

template <class T>
nn::Var<T> MsaeNet<T>::loss(nn::Tape<T>& tape, const nn::Bound<T>& p, const Matrix& x,
                            const std::vector<Matrix>& lambda, MsaeLossTerms* terms,
                            const std::vector<int>& levels, const Matrix* weights) const {
  int deepest = 0;
  const auto trains = training_levels(config_.levels(), levels, deepest);
  std::vector<Var> input(blocks_.size()), residual(blocks_.size()), masks(blocks_.size());
  input[0] = tape.constant(x);
  Var total, whole_xhat;
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Block& bl = blocks_[b];
    if (bl.level > deepest) break;
    if (bl.parent >= 0) {
      const auto pb = static_cast<std::size_t>(bl.parent);
      if (config_.attention) {  // diag(AM_slot) · residual: each vertex's 9 values times its weight
        Var w = nn::transpose(nn::slice_rows(masks[pb], Index{bl.slot}, Index{1}));  // [V, 1]
        w = nn::reshape(nn::mul(w, tape.constant(Matrix::Ones(n_vertices_, 9))), 1,
                        9 * Index{n_vertices_});
        input[b] = nn::mul(residual[pb], w);
      } else {
        input[b] = residual[pb];
      }
    }
    BlockOutput out = forward_block(p, static_cast<int>(b), input[b], &lambda[b],
                                    trains[static_cast<std::size_t>(bl.level)] ? &total : nullptr,
                                    terms, weights);
    residual[b] = out.residual;
    masks[b] = out.masks;
    if (config_.lambda_whole > 0)
      whole_xhat = whole_xhat.id < 0 ? out.xhat : nn::add(whole_xhat, out.xhat);
  }
  if (config_.lambda_whole > 0) {
    const Var e = nn::sub(input[0], whole_xhat);
    const Var whole = weights ? nn::scale(nn::sum_squares(e, weights), T(1) / weights->sum())
                              : nn::scale(nn::sum_squares(e), T(1) / static_cast<T>(x.rows()));
    const Var l = nn::scale(whole, static_cast<T>(config_.lambda_whole));
    total = total.id < 0 ? l : nn::add(total, l);
    if (terms) {
      terms->total += static_cast<double>(l.value()(0, 0));
      terms->whole += static_cast<double>(whole.value()(0, 0));
    }
  }
  return total;
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::subtree(int b, const Matrix& x,
                                                const std::vector<Matrix>& lambda,
                                                const std::vector<char>& trains,
                                                bool want_input_gradient, MsaeLossTerms& terms,
                                                const Matrix* weights, const Matrix* g_whole) {
  const Block& bl = blocks_[static_cast<std::size_t>(b)];
  nn::Tape<T> tape;
  const nn::Bound<T> p = bind_block(tape, b, true);
  Var in = want_input_gradient ? tape.variable(x) : tape.constant(x);
  Var total;
  BlockOutput out =
      forward_block(p, b, in, &lambda[static_cast<std::size_t>(b)],
                    trains[static_cast<std::size_t>(bl.level)] ? &total : nullptr, &terms, weights);
  // The whole reconstruction's term reaches x̂_b as ⟨x̂_b, G⟩ (every block visited lies at or above
  // the deepest level in training).
  if (g_whole) {
    Var s = nn::dot_constant(out.xhat, Matrix(*g_whole));
    total = total.id < 0 ? s : nn::add(total, s);
  }
  // Children, one at a time; their gradients w.r.t. their inputs become G_r and G_AM.
  bool children_train = false;
  for (std::size_t l = static_cast<std::size_t>(bl.level) + 1; l < trains.size(); ++l)
    children_train |= trains[l] != 0;
  if (children_train && !bl.children.empty()) {
    const Matrix& r = out.residual.value();
    const Matrix* am = config_.attention ? &out.masks.value() : nullptr;
    Matrix g_r = Matrix::Zero(r.rows(), r.cols());
    Matrix g_am = am ? Matrix::Zero(am->rows(), am->cols()) : Matrix();
    for (int child : bl.children) {
      const Block& cb = blocks_[static_cast<std::size_t>(child)];
      const Matrix g =
          subtree(child, child_input(cb, r, am), lambda, trains, true, terms, weights, g_whole);
      if (!am) {
        g_r += g;
        continue;
      }
      // Blocks of vertices in parallel: each owns its columns of g_r and its entries of g_am,
      // walked row by row (contiguous; one vertex down all rows touched a new page per row: 9.5%
      // of an MSAE step). Each g_am entry still sums the rows in order.
      constexpr Index kBlock = 64;
      const Index nv = n_vertices_;
      tbb::parallel_for(Index{0}, (nv + kBlock - 1) / kBlock, [&](Index blk) {
        const Index i0 = blk * kBlock, i1 = std::min(nv, i0 + kBlock);
        for (Index row = 0; row < r.rows(); ++row)
          for (Index i = i0; i < i1; ++i) {
            const auto gi = g.row(row).segment(9 * i, 9);
            g_r.row(row).segment(9 * i, 9) += gi * (*am)(cb.slot, i);
            g_am(cb.slot, i) += gi.dot(r.row(row).segment(9 * i, 9));
          }
      });
    }
    Var surrogate = nn::dot_constant(out.residual, std::move(g_r));
    if (am) surrogate = nn::add(surrogate, nn::dot_constant(out.masks, std::move(g_am)));
    total = total.id < 0 ? surrogate : nn::add(total, surrogate);
  }
  if (total.id < 0) return want_input_gradient ? Matrix::Zero(x.rows(), x.cols()) : Matrix();
  tape.backward(total);
  for (int k : bl.parameters()) {
    const Var& v = p.vars[static_cast<std::size_t>(k)];
    if (tape.has_grad(v.id)) store_.grad(k) += v.grad();
  }
  if (!want_input_gradient) return Matrix();
  return in.tape->has_grad(in.id) ? Matrix(in.grad()) : Matrix(Matrix::Zero(x.rows(), x.cols()));
}

template <class T>
MsaeLossTerms MsaeNet<T>::loss_and_gradient(const Matrix& x, const std::vector<Matrix>& lambda,
                                            const std::vector<int>& levels, const Matrix* weights) {
  int deepest = 0;
  const auto trains = training_levels(config_.levels(), levels, deepest);
  MsaeLossTerms terms;
  // The whole reconstruction's term needs x − Σ_b x̂_b before any block's backward pass: one more
  // forward pass (without tapes) gives it, and its gradient G = −2 λ_w w_r (x − Σ_b x̂_b)_r / Σ w
  // with respect to every x̂_b.
  Matrix g_whole;
  if (config_.lambda_whole > 0) {
    const Matrix e = x - reconstruct(x, deepest + 1);
    const T sum_w = weights ? weights->sum() : static_cast<T>(x.rows());
    const Eigen::Matrix<T, Eigen::Dynamic, 1> row_sq = e.rowwise().squaredNorm();
    const T whole = (weights ? row_sq.dot(weights->col(0)) : row_sq.sum()) / sum_w;
    g_whole = e * (T(-2) * static_cast<T>(config_.lambda_whole) / sum_w);
    if (weights) g_whole.array().colwise() *= weights->col(0).array();
    terms.total += config_.lambda_whole * static_cast<double>(whole);
    terms.whole += static_cast<double>(whole);
  }
  subtree(0, x, lambda, trains, false, terms, weights, g_whole.size() ? &g_whole : nullptr);
  return terms;
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::reconstruct(const Matrix& x, int levels,
                                                    std::vector<Matrix>* codes,
                                                    std::vector<Matrix>* inputs) const {
  if (levels < 1 || levels > config_.levels())
    throw UsageError(fmt::format("the model has levels 1..{}, not {}", config_.levels(), levels));
  Matrix sum = Matrix::Zero(x.rows(), x.cols());
  if (codes) codes->assign(blocks_.size(), Matrix());
  if (inputs) inputs->assign(blocks_.size(), Matrix());
  // Depth first, each block on its own small tape (constants only: no gradients are kept).
  std::vector<std::pair<int, Matrix>> todo = {{0, x}};
  while (!todo.empty()) {
    auto [b, input] = std::move(todo.back());
    todo.pop_back();
    const Block& bl = blocks_[static_cast<std::size_t>(b)];
    nn::Tape<T> tape;
    const nn::Bound<T> p = bind_block(tape, b, false);
    if (inputs) (*inputs)[static_cast<std::size_t>(b)] = input;
    Var in = tape.constant(std::move(input));
    BlockOutput out = forward_block(p, b, in, nullptr, nullptr, nullptr);
    sum += out.xhat.value();
    if (codes) (*codes)[static_cast<std::size_t>(b)] = out.z.value();
    if (bl.level + 1 >= levels) continue;
    const Matrix* am = config_.attention ? &out.masks.value() : nullptr;
    for (auto it = bl.children.rbegin(); it != bl.children.rend(); ++it)
      todo.emplace_back(
          *it, child_input(blocks_[static_cast<std::size_t>(*it)], out.residual.value(), am));
  }
  return sum;
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::decode(int block, const Matrix& z) const {
  nn::Tape<T> tape;
  return decoder(bind_block(tape, block, false), block, tape.constant(z)).value();
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::recombined_shapes(const Matrix& x, int count,
                                                          Rng& rng) const {
  std::vector<Matrix> codes;
  reconstruct(x, config_.levels(), &codes);
  Matrix shapes = Matrix::Zero(count, x.cols());
  for (std::size_t b = 0; b < codes.size(); ++b) {
    Matrix mixed(count, codes[b].cols());
    for (Eigen::Index j = 0; j < mixed.cols(); ++j)
      for (Eigen::Index r = 0; r < count; ++r)
        mixed(r, j) =
            codes[b](static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(x.rows()))), j);
    shapes += decode(static_cast<int>(b), mixed);
  }
  return shapes;
}

template <class T>
typename MsaeNet<T>::Matrix MsaeNet<T>::fit_codes(const Matrix& x, int levels,
                                                  std::vector<Matrix>& codes, int iterations,
                                                  double lr) const {
  if (levels < 1 || levels > config_.levels())
    throw UsageError(fmt::format("the model has levels 1..{}, not {}", config_.levels(), levels));
  const int n_blocks = level_begin_[static_cast<std::size_t>(levels)];
  if (static_cast<int>(codes.size()) < n_blocks)
    throw Error("internal: fit_codes needs every block's codes");
  // The codes of all blocks as one flat vector for Adam.
  Eigen::Index n_codes = 0;
  for (int b = 0; b < n_blocks; ++b) n_codes += codes[static_cast<std::size_t>(b)].size();
  nn::Vector<T> flat(n_codes), grad(n_codes);
  auto gather_codes = [&] {
    Eigen::Index at = 0;
    for (int b = 0; b < n_blocks; ++b) {
      const Matrix& z = codes[static_cast<std::size_t>(b)];
      flat.segment(at, z.size()) = Eigen::Map<const nn::Vector<T>>(z.data(), z.size());
      at += z.size();
    }
  };
  auto scatter_codes = [&] {
    Eigen::Index at = 0;
    for (int b = 0; b < n_blocks; ++b) {
      Matrix& z = codes[static_cast<std::size_t>(b)];
      Eigen::Map<nn::Vector<T>>(z.data(), z.size()) = flat.segment(at, z.size());
      at += z.size();
    }
  };
  gather_codes();
  nn::AdamOptions ao;
  ao.lr = lr;
  ao.schedule = nn::AdamOptions::Schedule::exponential;
  ao.decay_rate = 0.1;
  ao.decay_steps = std::max(1, iterations);
  nn::Adam<T> adam(static_cast<std::size_t>(n_codes), ao);
  Matrix recon;
  for (int it = 0; it <= iterations; ++it) {
    nn::Tape<T> tape;
    nn::Bound<T> p;
    p.vars.resize(store_.views().size());
    std::vector<Var> z(static_cast<std::size_t>(n_blocks));
    Var sum;
    for (int b = 0; b < n_blocks; ++b) {
      for (int k : blocks_[static_cast<std::size_t>(b)].parameters())
        p.vars[static_cast<std::size_t>(k)] = tape.constant(store_.value(k));
      z[static_cast<std::size_t>(b)] = tape.variable(codes[static_cast<std::size_t>(b)]);
      Var out = decoder(p, b, z[static_cast<std::size_t>(b)]);
      sum = b == 0 ? out : nn::add(sum, out);
    }
    recon = sum.value();
    if (it == iterations) break;
    tape.backward(nn::sum_squares(nn::sub(tape.constant(x), sum)));
    Eigen::Index at = 0;
    for (int b = 0; b < n_blocks; ++b) {
      const Matrix& g = z[static_cast<std::size_t>(b)].grad();
      grad.segment(at, g.size()) = Eigen::Map<const nn::Vector<T>>(g.data(), g.size());
      at += g.size();
    }
    adam.step(flat, grad);
    scatter_codes();
  }
  return recon;
}

template class MsaeNet<float>;
template class MsaeNet<double>;

}  // namespace df::models
