#include "models/msae/data.h"

#include <fmt/format.h>

#include "core/error.h"
#include "io/file_header.h"
#include "io/schema.h"

namespace df::models {

MsaeShapes read_msae_shapes(const MsaeModel& m, const std::string& path, const std::string& part) {
  io::Dimensions dims;
  h5::File in = io::open_input(path, "acap", &dims);
  if (!in.exists("/features/normalized"))
    throw InvalidInput("has no /features/normalized; run obj2acap on the meshes first", path);
  const io::Faces faces = in.read_matrix<int>("/template/faces");
  const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
  if (dims.at("V") != V || faces.rows() != m.tmpl.faces.rows() || faces != m.tmpl.faces)
    throw InvalidInput(
        fmt::format(
            "has another template than the model ({} vertices, {} triangles; the model's: {}, "
            "{}): the model only works on shapes of its own template",
            dims.at("V"), faces.rows(), V, m.tmpl.faces.rows()),
        path);
  const auto n = static_cast<std::int64_t>(dims.at("N"));
  MsaeShapes s;
  if (part == "all") {
    for (std::int64_t f = 0; f < n; ++f) s.frames.push_back(f);
  } else {
    if (part == "train")
      s.frames = m.split.train;
    else if (part == "validation")
      s.frames = m.split.validation;
    else if (part == "test")
      s.frames = m.split.test;
    else
      throw UsageError("--part must be train, validation, test or all");
    for (auto f : s.frames)
      if (f >= n)
        throw InvalidInput(
            fmt::format(
                "has {} frames, but the model's {} part names frame {}: give the file it was "
                "trained on ({}), or --part all",
                n, part, f, m.split.data),
            path);
  }
  s.history = io::read_history(in);
  s.offsets = in.read<std::int64_t>("/sequences/offsets").data;
  s.sequences = in.read_strings("/sequences/names");
  const auto names = in.read_strings("/frames/names");
  const geometry::Normalization nz = geometry::read_normalization(in);
  const bool renormalize = nz.min != m.normalization.min || nz.max != m.normalization.max;
  s.x.resize(static_cast<Eigen::Index>(s.frames.size()), 9 * static_cast<Eigen::Index>(V));
  std::size_t seq = 0;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const auto f = s.frames[k];
    in.read_rows<float>("/features/normalized", static_cast<std::size_t>(f), 1,
                        s.x.row(static_cast<Eigen::Index>(k)).data());
    io::check_finite_rows(s.x.row(static_cast<Eigen::Index>(k)).data(), static_cast<std::size_t>(f),
                          1, 9 * V, in.where("/features/normalized"));
    if (renormalize)
      for (Eigen::Index j = 0; j < s.x.cols(); ++j) {
        const int d = static_cast<int>(j % 9);
        float& v = s.x(static_cast<Eigen::Index>(k), j);
        v = static_cast<float>(m.normalization.normalize(d, nz.denormalize(d, v)));
      }
    s.names.push_back(names[static_cast<std::size_t>(f)]);
    if (f < s.offsets[seq]) seq = 0;  // frames come in increasing order; this only guards
    while (seq + 1 < s.offsets.size() && f >= s.offsets[seq + 1]) ++seq;
    s.sequence.push_back(s.sequences[seq]);
  }
  return s;
}

}  // namespace df::models
