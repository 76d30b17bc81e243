// Triangle meshes in and out. Reading: OBJ, OFF and PLY (ASCII and binary) through OpenMesh's
// readers with a verbatim importer (OBJ coordinates then re-parsed in double precision, as
// OpenMesh reads them as float), so vertices keep their file order, faces their file
// connectivity (polygons fan-triangulated), and a malformed file is an error instead of
// silently dropped or duplicated vertices (what OpenMesh's mesh kernel does on NaN or
// non-manifold input). Writing: OBJ/OFF/ASCII PLY formatted with fmt, because OpenMesh's
// writers are process-wide singletons that cannot run in parallel over frames.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace df::io {

/// What reading a mesh noticed but could continue past.
struct MeshReadReport {
  std::size_t polygons_triangulated = 0;  ///< faces with more than 3 corners
  std::size_t degenerate_faces = 0;       ///< repeated corner or zero area
  std::size_t nonmanifold_edges = 0;      ///< edges shared by more than two faces
  std::size_t isolated_vertices = 0;      ///< vertices in no face
  std::size_t dropped_faces = 0;          ///< OBJ faces with repeated corners (skipped)
};

/// A path's extension in lower case, with the dot (".obj"; "" if none).
std::string lower_extension(const std::string& path);
/// An HDF5 file name (.h5 or .hdf5): what tools write the file kinds to.
bool is_hdf5_path(const std::string& path);

/// The extensions read_mesh/write_mesh understand (lower case, with dot).
bool is_mesh_file(const std::string& path);

/// Reads a mesh file. Throws IOError (missing/unreadable) or InvalidInput (empty, not a mesh,
/// face index out of range, non-finite coordinates), naming the file. Non-manifold and
/// zero-area faces are counted in `report` (and warned about by the caller) but kept.
Mesh read_mesh(const std::string& path, MeshReadReport* report = nullptr);

/// Reads an OBJ frame known to share `reference`'s connectivity: positions only, parsed with
/// std::from_chars (several times faster than the general reader and thread-safe, so frames
/// can be read in parallel). Every face line is checked against the reference as it is parsed;
/// any difference, a NaN/Inf or unreadable coordinate, or a wrong vertex count is an
/// InvalidInput naming the file (and line), as read_mesh + check_same_connectivity would.
Vertices read_obj_frame(const std::string& path, const Mesh& reference,
                        const std::string& reference_name);

/// Logs one warning line per kind of problem in `report`, naming the file.
void warn_about(const MeshReadReport& report, const std::string& path);

/// Throws InvalidInput if `frame` does not have the reference's vertex count and faces, naming
/// the frame and the first differing face.
void check_same_connectivity(const Mesh& reference, const std::string& reference_name,
                             const Mesh& frame, const std::string& frame_name);

/// Writes meshes with one fixed connectivity; the format follows each file's extension
/// (.obj, .off, .ply). Builds OpenMesh's structure once, so writing many frames only sets
/// positions. Thread-safe for concurrent write() calls.
class MeshWriter {
 public:
  explicit MeshWriter(const Faces& faces, std::size_t n_vertices);
  ~MeshWriter();
  /// @param path   output file; its extension picks the format
  /// @param V      #V by 3 positions
  void write(const std::string& path, const Vertices& V) const;

 private:
  Faces faces_;
  std::size_t n_vertices_;
};

/// Writes one mesh (convenience over MeshWriter).
void write_mesh(const std::string& path, const Mesh& mesh);

}  // namespace df::io
