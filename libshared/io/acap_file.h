// The ACAP file kind (schemas/acap.json): mesh frames on one template, their ACAP features (raw
// and normalized) and the numbers that normalized them, sequences (CSR offsets), optional class
// labels, and for generated frames where they come from. The only place that names its datasets:
// every tool reads it through AcapReader and writes it through AcapWriter (as io/skeleton_file
// owns the skeleton kind). The template group and /normalization, which the model and
// components kinds carry too, are read and written here for all of them.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/feature_normalization.h"
#include "core/mesh.h"
#include "io/h5.h"
#include "io/mesh_io.h"
#include "io/schema.h"

namespace df::io {

/// Writes /normalization (mode, range, min, max) into a file of any kind that carries it.
void write_normalization(h5::File& f, const FeatureNormalization& nz);
/// Reads /normalization; InvalidInput naming the file when it is absent.
FeatureNormalization read_normalization(const h5::File& f);

/// /template/vertices and /template/faces, in every kind that has a template.
void write_template(h5::File& f, const Mesh& tmpl);
Mesh read_template(const h5::File& f);

/// What synth-meshseq made and planted (/synthetic): its parameters and, for the bumps, the
/// regions with their scale, centre and weight in every frame — the ground truth of eval-metrics'
/// localization scores.
struct SyntheticTruth {
  std::string kind;
  double amplitude = 0, twist_degrees = 0, periods = 0;
  std::int64_t resolution = 0, seed = 0;
  std::vector<std::vector<std::uint8_t>> regions;         ///< [R][V] 1 inside region r
  std::vector<std::int32_t> region_scale, region_center;  ///< [R]
  std::vector<float> weights;                             ///< [N, R]
};

/// What edit-shape did to make a shape (/edit): the weights of every component of the components
/// file it used (levels in order, pruned ones with weight 0), which of them this edit solved for,
/// the handles and their targets, and how far the weights alone reach each target.
struct ShapeEdit {
  std::string components;  ///< the components file as given
  double l2 = 0;
  std::int64_t iterations = 0;
  bool converged = false;
  std::vector<double> weights;        ///< [K]
  std::vector<std::int32_t> level;    ///< [K] the level of each component
  std::vector<std::uint8_t> edited;   ///< [K] 1 = solved in this edit, 0 = kept from --from
  std::vector<std::int32_t> handles;  ///< [H] vertices held
  std::vector<double> targets;        ///< [H, 3]
  std::vector<double> residual;       ///< [H] see edit-shape --help
  std::vector<double> energy;         ///< the energy at the start and after each step
};

/// An ACAP input, opened and validated (io::open_input) once; partial reads by frame.
class AcapReader {
 public:
  explicit AcapReader(const std::string& path);

  const std::string& path() const { return path_; }
  std::size_t frames() const { return dims_.at("N"); }
  std::size_t vertices() const { return dims_.at("V"); }
  std::string history() const;

  Mesh read_template() const;
  Faces read_faces() const;
  /// InvalidInput naming the file unless its template has `tmpl`'s vertex count and faces;
  /// `whose` names the other side ("the model", "the components file").
  void require_template(const Mesh& tmpl, const std::string& whose) const;
  /// Frame `frame`'s stored positions [V, 3] (has_positions first); InvalidInput for a frame
  /// out of range.
  Vertices read_frame_positions(std::size_t frame) const;
  std::vector<std::string> frame_names() const;
  std::vector<std::string> sequence_names() const;
  std::vector<std::int64_t> offsets() const;  ///< [S+1]
  bool labelled() const;
  std::vector<std::int32_t> labels() const;  ///< [S] (labelled files only)
  std::vector<std::string> class_names() const;
  /// Per sequence its class name, "" for every sequence of an unlabelled file.
  std::vector<std::string> sequence_labels() const;
  bool has_source() const;
  std::vector<std::int64_t> source() const;  ///< generated frames' data frame (has_source)
  bool has_steps() const;
  std::vector<std::int32_t> steps() const;

  bool has_positions() const;
  bool has_raw() const;
  bool has_normalized() const;
  bool has_normalization() const;
  FeatureNormalization normalization() const;
  /// Planted regions (synth-meshseq --kind bumps): masks [R][V] and scales; has_regions first.
  bool has_regions() const;
  /// The /edit record of a shape made by edit-shape; has_edit first.
  bool has_edit() const;
  ShapeEdit read_edit() const;
  void read_regions(std::vector<std::vector<std::uint8_t>>& masks,
                    std::vector<std::int32_t>& scale) const;

  /// Rows [first, first + count) (a row: one frame, V x 3 or V x 9 values), checked finite.
  void read_positions(std::size_t first, std::size_t count, float* out) const;
  void read_raw(std::size_t first, std::size_t count, double* out) const;
  void read_normalized(std::size_t first, std::size_t count, float* out) const;
  /// Raw features of rows [first, first + count): /features/raw when stored, else
  /// /features/normalized with the file's normalization undone; InvalidInput when it has neither.
  void read_features(std::size_t first, std::size_t count, double* out) const;

 private:
  std::string path_;
  Dimensions dims_;
  h5::File file_;
};

/// Writes an ACAP file (into an AtomicOutput's temporary path): the header first, then any of
/// the parts, each at most once.
class AcapWriter {
 public:
  /// @param display     the final path, for messages
  /// @param histories   the inputs' history attributes (io::write_header)
  AcapWriter(const std::string& temp_path, const std::string& display,
             const std::vector<std::string>& histories = {});

  void write_template(const Mesh& tmpl);
  void write_normalization(const FeatureNormalization& nz);
  void write_frame_names(const std::vector<std::string>& names);
  void write_sequences(const std::vector<std::int64_t>& offsets,
                       const std::vector<std::string>& names);
  void write_labels(const std::vector<std::int32_t>& labels,
                    const std::vector<std::string>& class_names);
  /// Generated frames: the data frame at the same time (-1 past its end); `data` the data file,
  /// `method` what made them ("" = not recorded).
  void write_source(const std::vector<std::int64_t>& source, const std::string& data,
                    const std::string& method = {});
  void write_steps(const std::vector<std::int32_t>& steps);
  /// /synthetic: the parameters always, the regions, scales, centres and weights when there are.
  void write_synthetic(const SyntheticTruth& truth);
  void write_edit(const ShapeEdit& edit);

  /// Datasets of `frames` x V rows, created empty and written in row blocks, or written whole.
  void create_positions(std::size_t frames, std::size_t vertices);
  void write_positions_rows(std::size_t first, std::size_t count, const float* data);
  void create_raw(std::size_t frames, std::size_t vertices);
  void write_raw_rows(std::size_t first, std::size_t count, const double* data);
  void create_normalized(std::size_t frames, std::size_t vertices);
  void write_normalized_rows(std::size_t first, std::size_t count, const float* data);
  void write_positions(std::size_t frames, std::size_t vertices, const float* data);
  void write_normalized(std::size_t frames, std::size_t vertices, const float* data);
  /// Reads back raw rows written before (obj2acap normalizes in a second pass).
  void read_raw_rows(std::size_t first, std::size_t count, double* out) const;

  void close();

 private:
  h5::File file_;
};

}  // namespace df::io
