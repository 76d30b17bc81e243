#include "io/acap_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <span>

#include "core/error.h"
#include "io/file_header.h"

namespace df::io {
namespace {

constexpr const char* kVertices = "/template/vertices";
constexpr const char* kFaces = "/template/faces";
constexpr const char* kNormalization = "/normalization";
constexpr const char* kNormMin = "/normalization/min";
constexpr const char* kNormMax = "/normalization/max";
constexpr const char* kPositions = "/frames/positions";
constexpr const char* kFrameNames = "/frames/names";
constexpr const char* kSource = "/frames/source";
constexpr const char* kSteps = "/frames/step";
constexpr const char* kOffsets = "/sequences/offsets";
constexpr const char* kSequenceNames = "/sequences/names";
constexpr const char* kLabels = "/sequences/labels";
constexpr const char* kClassNames = "/classes/names";
constexpr const char* kRaw = "/features/raw";
constexpr const char* kNormalized = "/features/normalized";
constexpr const char* kSynthetic = "/synthetic";
constexpr const char* kRegions = "/synthetic/regions";
constexpr const char* kRegionScale = "/synthetic/region_scale";
constexpr const char* kRegionCenter = "/synthetic/region_center";
constexpr const char* kRegionWeights = "/synthetic/weights";
constexpr const char* kEdit = "/edit";
constexpr const char* kEditWeights = "/edit/weights";
constexpr const char* kEditLevel = "/edit/level";
constexpr const char* kEdited = "/edit/edited";
constexpr const char* kHandles = "/edit/handles";
constexpr const char* kTargets = "/edit/targets";
constexpr const char* kHandleResidual = "/edit/residual";
constexpr const char* kEditEnergy = "/edit/energy";
constexpr std::size_t kDims = kAcapFeatureDims;

}  // namespace

void write_normalization(h5::File& f, const FeatureNormalization& nz) {
  f.create_groups(kNormalization);
  f.set_attr(kNormalization, "mode", nz.mode == NormalizationMode::group ? "group" : "per-dim");
  f.set_attr(kNormalization, "range", std::string("[-0.95, 0.95]"));
  f.write<double>(kNormMin, std::span<const double>(nz.min), {kDims});
  f.write<double>(kNormMax, std::span<const double>(nz.max), {kDims});
}

FeatureNormalization read_normalization(const h5::File& f) {
  if (!f.exists(kNormMin) || !f.exists(kNormMax))
    throw InvalidInput("has no /normalization (min and max)", f.name());
  FeatureNormalization nz;
  nz.mode = f.has_attr(kNormalization, "mode") && f.attr_string(kNormalization, "mode") == "per-dim"
                ? NormalizationMode::per_dim
                : NormalizationMode::group;
  auto lo = f.read<double>(kNormMin).data, hi = f.read<double>(kNormMax).data;
  if (lo.size() != kDims || hi.size() != kDims)
    throw InvalidInput("/normalization/min and max must hold 9 numbers", f.name());
  std::copy(lo.begin(), lo.end(), nz.min.begin());
  std::copy(hi.begin(), hi.end(), nz.max.begin());
  return nz;
}

void write_template(h5::File& f, const Mesh& tmpl) {
  f.write_matrix(kVertices, tmpl.vertices);
  f.write_matrix(kFaces, tmpl.faces);
}

Mesh read_template(const h5::File& f) {
  return Mesh{f.read_matrix<double>(kVertices), f.read_matrix<int>(kFaces)};
}

// --- AcapReader

AcapReader::AcapReader(const std::string& path)
    : path_(path), file_(open_input(path, "acap", &dims_)) {}

std::string AcapReader::history() const {
  return read_history(file_);
}
Mesh AcapReader::read_template() const {
  return io::read_template(file_);
}
Faces AcapReader::read_faces() const {
  return file_.read_matrix<int>(kFaces);
}
std::vector<std::string> AcapReader::frame_names() const {
  return file_.read_strings(kFrameNames);
}
std::vector<std::string> AcapReader::sequence_names() const {
  return file_.read_strings(kSequenceNames);
}
std::vector<std::int64_t> AcapReader::offsets() const {
  return file_.read<std::int64_t>(kOffsets).data;
}
bool AcapReader::labelled() const {
  return file_.exists(kLabels);
}
std::vector<std::int32_t> AcapReader::labels() const {
  return file_.read<std::int32_t>(kLabels).data;
}
std::vector<std::string> AcapReader::class_names() const {
  return file_.read_strings(kClassNames);
}

std::vector<std::string> AcapReader::sequence_labels() const {
  std::vector<std::string> out(sequence_names().size());
  if (!labelled()) return out;
  const auto l = labels();
  const auto classes = class_names();
  for (std::size_t s = 0; s < l.size(); ++s) out[s] = classes[static_cast<std::size_t>(l[s])];
  return out;
}

bool AcapReader::has_source() const {
  return file_.exists(kSource);
}
std::vector<std::int64_t> AcapReader::source() const {
  return file_.read<std::int64_t>(kSource).data;
}
bool AcapReader::has_steps() const {
  return file_.exists(kSteps);
}
std::vector<std::int32_t> AcapReader::steps() const {
  return file_.read<std::int32_t>(kSteps).data;
}
bool AcapReader::has_positions() const {
  return file_.exists(kPositions);
}
bool AcapReader::has_raw() const {
  return file_.exists(kRaw);
}
bool AcapReader::has_normalized() const {
  return file_.exists(kNormalized);
}
bool AcapReader::has_normalization() const {
  return file_.exists(kNormMin);
}
FeatureNormalization AcapReader::normalization() const {
  return read_normalization(file_);
}
bool AcapReader::has_regions() const {
  return file_.exists(kRegions);
}

void AcapReader::read_regions(std::vector<std::vector<std::uint8_t>>& masks,
                              std::vector<std::int32_t>& scale) const {
  const auto m = file_.read<std::uint8_t>(kRegions);
  const std::size_t R = m.dims[0], V = m.dims[1];
  masks.assign(R, {});
  for (std::size_t r = 0; r < R; ++r)
    masks[r].assign(m.data.begin() + static_cast<std::ptrdiff_t>(r * V),
                    m.data.begin() + static_cast<std::ptrdiff_t>((r + 1) * V));
  scale = file_.read<std::int32_t>(kRegionScale).data;
}

void AcapReader::require_template(const Mesh& tmpl, const std::string& whose) const {
  const Faces faces = read_faces();
  if (vertices() != static_cast<std::size_t>(tmpl.vertices.rows()) ||
      faces.rows() != tmpl.faces.rows())
    throw InvalidInput(
        fmt::format("has another template than {0} ({1} vertices, {2} triangles; {0}'s: {3}, {4}): "
                    "the two must share the template",
                    whose, vertices(), faces.rows(), tmpl.vertices.rows(), tmpl.faces.rows()),
        path_);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    if (faces.row(f) != tmpl.faces.row(f))
      throw InvalidInput(
          fmt::format("has another template than {0}: the same {1} vertices and {2} triangles, but "
                      "triangle {3} joins vertices ({4} {5} {6}) here and ({7} {8} {9}) in {0} "
                      "(counting from 0): the two must share the template",
                      whose, vertices(), faces.rows(), f, faces(f, 0), faces(f, 1), faces(f, 2),
                      tmpl.faces(f, 0), tmpl.faces(f, 1), tmpl.faces(f, 2)),
          path_);
}

Vertices AcapReader::read_frame_positions(std::size_t frame) const {
  if (frame >= frames())
    throw InvalidInput(fmt::format("has frames 0..{}, not {}", frames() - 1, frame), path_);
  std::vector<float> p(vertices() * 3);
  read_positions(frame, 1, p.data());
  return Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
             p.data(), static_cast<Eigen::Index>(vertices()), 3)
      .cast<double>();
}

bool AcapReader::has_edit() const {
  return file_.exists(kEdit);
}

ShapeEdit AcapReader::read_edit() const {
  ShapeEdit e;
  e.components = file_.attr_string(kEdit, "components");
  e.l2 = file_.attr_double(kEdit, "l2");
  e.iterations = file_.attr_int(kEdit, "iterations");
  e.converged = file_.attr_int(kEdit, "converged") != 0;
  e.weights = file_.read<double>(kEditWeights).data;
  e.level = file_.read<std::int32_t>(kEditLevel).data;
  e.edited = file_.read<std::uint8_t>(kEdited).data;
  e.handles = file_.read<std::int32_t>(kHandles).data;
  e.targets = file_.read<double>(kTargets).data;
  e.residual = file_.read<double>(kHandleResidual).data;
  e.energy = file_.read<double>(kEditEnergy).data;
  return e;
}

void AcapReader::read_positions(std::size_t first, std::size_t count, float* out) const {
  file_.read_rows<float>(kPositions, first, count, out);
  check_finite_rows(out, first, count, vertices() * 3, file_.where(kPositions));
}

void AcapReader::read_raw(std::size_t first, std::size_t count, double* out) const {
  file_.read_rows<double>(kRaw, first, count, out);
  check_finite_rows(out, first, count, vertices() * kDims, file_.where(kRaw));
}

void AcapReader::read_normalized(std::size_t first, std::size_t count, float* out) const {
  file_.read_rows<float>(kNormalized, first, count, out);
  check_finite_rows(out, first, count, vertices() * kDims, file_.where(kNormalized));
}

void AcapReader::read_features(std::size_t first, std::size_t count, double* out) const {
  if (has_raw()) return read_raw(first, count, out);
  if (!has_normalized())
    throw InvalidInput(
        "has no ACAP features (/features/raw or /features/normalized): run obj2acap on it first",
        path_);
  const std::size_t n = count * vertices() * kDims;
  std::vector<float> x(n);
  read_normalized(first, count, x.data());
  const auto nz = normalization();
  for (std::size_t j = 0; j < n; ++j) out[j] = nz.denormalize(static_cast<int>(j % kDims), x[j]);
}

// --- AcapWriter

AcapWriter::AcapWriter(const std::string& temp_path, const std::string& display,
                       const std::vector<std::string>& histories)
    : file_(temp_path, h5::File::Mode::create, display) {
  write_header(file_, "acap", histories);
}

void AcapWriter::write_template(const Mesh& tmpl) {
  io::write_template(file_, tmpl);
}
void AcapWriter::write_normalization(const FeatureNormalization& nz) {
  io::write_normalization(file_, nz);
}
void AcapWriter::write_frame_names(const std::vector<std::string>& names) {
  file_.write_strings(kFrameNames, names);
}

void AcapWriter::write_sequences(const std::vector<std::int64_t>& offsets,
                                 const std::vector<std::string>& names) {
  file_.write<std::int64_t>(kOffsets, offsets, {offsets.size()});
  file_.write_strings(kSequenceNames, names);
}

void AcapWriter::write_labels(const std::vector<std::int32_t>& labels,
                              const std::vector<std::string>& class_names) {
  file_.write<std::int32_t>(kLabels, labels, {labels.size()});
  file_.write_strings(kClassNames, class_names);
}

void AcapWriter::write_source(const std::vector<std::int64_t>& source, const std::string& data,
                              const std::string& method) {
  file_.write<std::int64_t>(kSource, source, {source.size()});
  file_.set_attr(kSource, "data", data);
  if (!method.empty()) file_.set_attr(kSource, "method", method);
}

void AcapWriter::write_steps(const std::vector<std::int32_t>& steps) {
  file_.write<std::int32_t>(kSteps, steps, {steps.size()});
}

void AcapWriter::write_synthetic(const SyntheticTruth& t) {
  file_.create_groups(kSynthetic);
  file_.set_attr(kSynthetic, "generator", std::string("synth-meshseq"));
  file_.set_attr(kSynthetic, "kind", t.kind);
  file_.set_attr(kSynthetic, "amplitude", t.amplitude);
  file_.set_attr(kSynthetic, "twist_degrees", t.twist_degrees);
  file_.set_attr(kSynthetic, "periods", t.periods);
  file_.set_attr(kSynthetic, "resolution", t.resolution);
  file_.set_attr(kSynthetic, "seed", t.seed);
  if (t.regions.empty()) return;
  const std::size_t R = t.regions.size(), V = t.regions.front().size();
  h5::Array<std::uint8_t> masks{{R, V}, {}};
  for (const auto& r : t.regions) masks.data.insert(masks.data.end(), r.begin(), r.end());
  file_.write(kRegions, masks);
  file_.write<std::int32_t>(kRegionScale, t.region_scale, {R});
  file_.write<std::int32_t>(kRegionCenter, t.region_center, {R});
  file_.write(kRegionWeights, h5::Array<float>{{t.weights.size() / R, R}, t.weights});
}

void AcapWriter::write_edit(const ShapeEdit& e) {
  file_.create_groups(kEdit);
  file_.set_attr(kEdit, "components", e.components);
  file_.set_attr(kEdit, "l2", e.l2);
  file_.set_attr(kEdit, "iterations", e.iterations);
  file_.set_attr(kEdit, "converged", static_cast<std::int64_t>(e.converged));
  file_.write<double>(kEditWeights, e.weights, {e.weights.size()});
  file_.write<std::int32_t>(kEditLevel, e.level, {e.level.size()});
  file_.write<std::uint8_t>(kEdited, e.edited, {e.edited.size()});
  file_.write<std::int32_t>(kHandles, e.handles, {e.handles.size()});
  file_.write<double>(kTargets, e.targets, {e.handles.size(), 3});
  file_.write<double>(kHandleResidual, e.residual, {e.residual.size()});
  file_.write<double>(kEditEnergy, e.energy, {e.energy.size()});
}

void AcapWriter::create_positions(std::size_t frames, std::size_t vertices) {
  file_.create<float>(kPositions, {frames, vertices, 3});
}
void AcapWriter::write_positions_rows(std::size_t first, std::size_t count, const float* data) {
  file_.write_rows<float>(kPositions, first, count, data);
}
void AcapWriter::create_raw(std::size_t frames, std::size_t vertices) {
  file_.create<double>(kRaw, {frames, vertices, kDims});
}
void AcapWriter::write_raw_rows(std::size_t first, std::size_t count, const double* data) {
  file_.write_rows<double>(kRaw, first, count, data);
}
void AcapWriter::create_normalized(std::size_t frames, std::size_t vertices) {
  file_.create<float>(kNormalized, {frames, vertices, kDims});
}
void AcapWriter::write_normalized_rows(std::size_t first, std::size_t count, const float* data) {
  file_.write_rows<float>(kNormalized, first, count, data);
}
void AcapWriter::write_positions(std::size_t frames, std::size_t vertices, const float* data) {
  file_.write<float>(kPositions, std::span<const float>(data, frames * vertices * 3),
                     {frames, vertices, 3});
}
void AcapWriter::write_normalized(std::size_t frames, std::size_t vertices, const float* data) {
  file_.write<float>(kNormalized, std::span<const float>(data, frames * vertices * kDims),
                     {frames, vertices, kDims});
}

void AcapWriter::read_raw_rows(std::size_t first, std::size_t count, double* out) const {
  file_.read_rows<double>(kRaw, first, count, out);
}

void AcapWriter::close() {
  file_.close();
}

}  // namespace df::io
