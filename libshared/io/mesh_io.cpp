#include "io/mesh_io.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "core/log.h"
#include "io/file_bytes.h"
#include "io/mesh_check.h"

namespace fs = std::filesystem;

namespace df::io {
namespace {

// OpenMesh prints its complaints on its own streams; route them into a buffer so that they
// become our messages (and never reach the terminal raw). Connected once per process and never
// disconnected: OpenMesh's multiplex_streambuf::disconnect does not free the target that
// connect allocated (a leak per read, found by fuzzing), and an immortal buffer also outlives
// OpenMesh's own static streams at exit. Used under g_openmesh_mutex.
std::mutex g_openmesh_mutex;
class OpenMeshMessages {
 public:
  static OpenMeshMessages& instance() {
    static auto* messages = new OpenMeshMessages;  // intentionally never destroyed
    return *messages;
  }
  std::string take() {
    std::string s = text_.str();
    text_.str("");
    return s;
  }

 private:
  OpenMeshMessages() {
    omerr().connect(text_);
    omerr().disconnect(std::cerr);
    omlog().connect(text_);
    omlog().disconnect(std::cerr);
    omout().connect(text_);
    omout().disconnect(std::cout);
  }
  std::ostringstream text_;
};

// Records what a reader delivers, verbatim: no kernel, no manifold repairs.
class VerbatimImporter : public OpenMesh::IO::BaseImporter {
 public:
  using VH = OpenMesh::VertexHandle;
  using FH = OpenMesh::FaceHandle;
  using HH = OpenMesh::HalfedgeHandle;
  using EH = OpenMesh::EdgeHandle;

  std::vector<OpenMesh::Vec3d> points;
  std::vector<std::vector<int>> polygons;

  VH add_vertex(const OpenMesh::Vec3f& p) override { return add_vertex(OpenMesh::Vec3d(p)); }
  VH add_vertex(const OpenMesh::Vec3d& p) override {
    points.push_back(p);
    return VH(static_cast<int>(points.size()) - 1);
  }
  VH add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  HH add_edge(VH, VH) override { return HH(); }
  FH add_face(const VHandles& idx) override {
    std::vector<int> poly;
    poly.reserve(idx.size());
    for (const auto& v : idx) poly.push_back(v.idx());
    polygons.push_back(std::move(poly));
    return FH(static_cast<int>(polygons.size()) - 1);
  }
  FH add_face(HH) override { return FH(); }
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FH, int) override {}
  void set_point(VH v, const OpenMesh::Vec3f& p) override {
    if (v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < points.size())
      points[v.idx()] = OpenMesh::Vec3d(p);
  }
  void set_halfedge(VH, HH) override {}
  void set_normal(VH, const OpenMesh::Vec3f&) override {}
  void set_normal(VH, const OpenMesh::Vec3d&) override {}
  void set_color(VH, const OpenMesh::Vec3uc&) override {}
  void set_color(VH, const OpenMesh::Vec4uc&) override {}
  void set_color(VH, const OpenMesh::Vec3f&) override {}
  void set_color(VH, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VH, const OpenMesh::Vec2f&) override {}
  void set_status(VH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HH, HH) override {}
  void set_face(HH, FH) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HH, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VH, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HH, const OpenMesh::Vec3f&) override {}
  void set_status(HH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EH, const OpenMesh::Vec3uc&) override {}
  void set_color(EH, const OpenMesh::Vec4uc&) override {}
  void set_color(EH, const OpenMesh::Vec3f&) override {}
  void set_color(EH, const OpenMesh::Vec4f&) override {}
  void set_status(EH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FH, const OpenMesh::Vec3f&) override {}
  void set_normal(FH, const OpenMesh::Vec3d&) override {}
  void set_color(FH, const OpenMesh::Vec3uc&) override {}
  void set_color(FH, const OpenMesh::Vec4uc&) override {}
  void set_color(FH, const OpenMesh::Vec3f&) override {}
  void set_color(FH, const OpenMesh::Vec4f&) override {}
  void set_status(FH, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  std::size_t n_vertices() const override { return points.size(); }
  std::size_t n_faces() const override { return polygons.size(); }
  std::size_t n_edges() const override { return 0; }
};

}  // namespace

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

bool is_hdf5_path(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".h5" || e == ".hdf5";
}

bool is_mesh_file(const std::string& path) {
  std::string e = lower_extension(path);
  return e == ".obj" || e == ".off" || e == ".ply";
}

namespace {

std::string first_line(const std::string& s) {
  return s.substr(0, s.find('\n'));
}

// OpenMesh's reader into `importer`; its messages (empty when it said nothing). Throws when it
// fails or finds no vertices or no faces.
std::string import_with_openmesh(const std::string& path, VerbatimImporter& importer) {
  std::string messages;
  bool ok = false;
  {
    std::lock_guard lock(g_openmesh_mutex);  // OpenMesh's streams and IOManager are global
    OpenMeshMessages& capture = OpenMeshMessages::instance();
    capture.take();  // nothing left from elsewhere
    OpenMesh::IO::Options opt;
    ok = OpenMesh::IO::IOManager().read(path, importer, opt);
    messages = capture.take();
  }
  if (!ok)
    throw InvalidInput(messages.empty() ? "cannot read as a mesh"
                                        : "cannot read as a mesh: " + first_line(messages),
                       path);
  if (importer.points.empty()) throw InvalidInput("no vertices found; not a mesh file?", path);
  if (importer.polygons.empty())
    throw InvalidInput("no faces found (a point cloud is not a mesh)", path);
  return messages;
}

Vertices finite_vertices(const VerbatimImporter& importer, const std::string& path) {
  const auto nv = importer.points.size();
  Vertices v(static_cast<Eigen::Index>(nv), 3);
  for (std::size_t i = 0; i < nv; ++i) {
    for (int k = 0; k < 3; ++k) {
      double x = importer.points[i][k];
      if (!std::isfinite(x))
        throw InvalidInput(fmt::format("vertex {} has a non-finite coordinate ({})", i + 1, x),
                           path);
      v(static_cast<Eigen::Index>(i), k) = x;
    }
  }
  return v;
}

// The polygons as triangle fans, each checked; counts the polygons it split.
std::vector<std::array<int, 3>> fan_triangles(const VerbatimImporter& importer,
                                              const std::string& path, MeshReadReport& rep) {
  const auto nv = importer.points.size();
  std::vector<std::array<int, 3>> tris;
  tris.reserve(importer.polygons.size());
  for (std::size_t f = 0; f < importer.polygons.size(); ++f) {
    const auto& poly = importer.polygons[f];
    if (poly.size() < 3)
      throw InvalidInput(fmt::format("face {} has {} corners", f + 1, poly.size()), path);
    for (int v : poly)
      if (v < 0 || static_cast<std::size_t>(v) >= nv)
        throw InvalidInput(fmt::format("face {} refers to vertex {} of {}", f + 1, v + 1, nv),
                           path);
    if (poly.size() > 3) ++rep.polygons_triangulated;
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      tris.push_back({poly[0], poly[k], poly[k + 1]});
  }
  return tris;
}

// The mesh's faces from `tris`, counting degenerate faces, edges of more than two faces and
// vertices of none.
void set_faces(Mesh& mesh, const std::vector<std::array<int, 3>>& tris, MeshReadReport& rep) {
  mesh.faces.resize(static_cast<Eigen::Index>(tris.size()), 3);
  std::vector<char> used(static_cast<std::size_t>(mesh.vertices.rows()), 0);
  std::map<std::pair<int, int>, int> edge_faces;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const auto& t = tris[f];
    for (int k = 0; k < 3; ++k) {
      mesh.faces(static_cast<Eigen::Index>(f), k) = t[k];
      used[t[k]] = 1;
      int a = t[k], b = t[(k + 1) % 3];
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
    Eigen::Vector3d e1 = mesh.vertices.row(t[1]) - mesh.vertices.row(t[0]);
    Eigen::Vector3d e2 = mesh.vertices.row(t[2]) - mesh.vertices.row(t[0]);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || e1.cross(e2).norm() == 0.0)
      ++rep.degenerate_faces;
  }
  for (const auto& [edge, count] : edge_faces)
    if (count > 2) ++rep.nonmanifold_edges;
  rep.isolated_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
}

}  // namespace

Mesh read_mesh(const std::string& path, MeshReadReport* report) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError("no such file", path);
  if (fs::is_directory(path, ec)) throw InvalidInput("is a directory, not a mesh file", path);
  if (!is_mesh_file(path))
    throw InvalidInput("unknown mesh format (expected .obj, .off or .ply)", path);
  if (fs::file_size(path, ec) == 0) throw InvalidInput("empty file", path);
  const std::string ext = lower_extension(path);
  // what OpenMesh's readers cannot survive, and the OBJ line counts they hide
  const MeshTextScan scan = check_mesh_structure(path, ext);

  VerbatimImporter importer;
  const std::string messages = import_with_openmesh(path, importer);
  const auto nv = importer.points.size();
  if (ext == ".obj" && scan.obj_vertex_lines != nv)
    throw InvalidInput(
        fmt::format("{} of {} vertex lines could not be read (non-numeric coordinates?)",
                    scan.obj_vertex_lines - std::min(scan.obj_vertex_lines, nv),
                    scan.obj_vertex_lines),
        path);
  Mesh mesh;
  mesh.vertices = finite_vertices(importer, path);

  MeshReadReport rep;
  if (ext == ".obj" && scan.obj_face_lines > importer.polygons.size())
    rep.dropped_faces = scan.obj_face_lines - importer.polygons.size();
  if (!messages.empty()) log::debug("{}: OpenMesh: {}", path, first_line(messages));
  set_faces(mesh, fan_triangles(importer, path, rep), rep);
  // OpenMesh's OBJ reader parses coordinates as float; take them again in double precision.
  if (ext == ".obj") mesh.vertices = read_obj_frame(path, mesh, path);
  if (report) *report = rep;
  return mesh;
}

namespace {

void skip_blank(const char*& q, const char* e) {
  while (q < e && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
}

// A "v x y z" line's coordinates (q after the "v ") into row v.
void parse_vertex(const char* q, const char* eol, Vertices& V, Eigen::Index v,
                  const std::string& path, std::size_t line) {
  for (int k = 0; k < 3; ++k) {
    skip_blank(q, eol);
    double x = 0;
    if (q + 1 < eol && q[0] == '+' && q[1] != '-' && q[1] != '+') ++q;  // "+1.5", as strtod
    auto [ptr, ec] = std::from_chars(q, eol, x);
    if (ec != std::errc() || !std::isfinite(x))
      throw InvalidInput(
          ec != std::errc() ? "unreadable vertex coordinate" : "non-finite coordinate (NaN or Inf)",
          path + ":" + std::to_string(line));
    q = ptr;
    V(v, k) = x;
  }
}

// An "f ..." line's corners (q after the "f "), 0-based, `read` vertices read so far; a corner
// that repeats an earlier one is left out, as the general reader (OpenMesh) takes a face.
void parse_face(const char* q, const char* eol, Eigen::Index read, std::vector<int>& poly,
                const std::string& path, std::size_t line) {
  auto where = [&] { return path + ":" + std::to_string(line); };
  poly.clear();
  while (true) {
    skip_blank(q, eol);
    if (q >= eol) break;
    long idx = 0;
    if (q + 1 < eol && q[0] == '+' && q[1] != '-' && q[1] != '+') ++q;
    auto [ptr, ec] = std::from_chars(q, eol, idx);
    if (ec != std::errc()) throw InvalidInput("unreadable face", where());
    // 1-based; negative = relative to the vertices read so far
    poly.push_back(static_cast<int>(idx > 0 ? idx - 1 : read + idx));
    q = ptr;
    while (q < eol && *q != ' ' && *q != '\t' && *q != '\r') ++q;  // skip /vt/vn
  }
  if (poly.size() < 3)
    throw InvalidInput(fmt::format("face with {} corners", poly.size()), where());
  for (std::size_t k = 1; k < poly.size();) {
    if (std::find(poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(k), poly[k]) !=
        poly.begin() + static_cast<std::ptrdiff_t>(k))
      poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(k));
    else
      ++k;
  }
}

// The face's fan against the reference's triangles from `tri` on; advances `tri`.
void match_fan(const std::vector<int>& poly, const Mesh& reference,
               const std::string& reference_name, Eigen::Index& tri, const std::string& path) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k, ++tri) {
    if (tri >= reference.faces.rows())
      throw InvalidInput(fmt::format("has more triangles than the reference {} ({})",
                                     reference_name, reference.faces.rows()),
                         path);
    if (reference.faces(tri, 0) != poly[0] || reference.faces(tri, 1) != poly[k] ||
        reference.faces(tri, 2) != poly[k + 1])
      throw InvalidInput(fmt::format("connectivity differs from the reference {} first at "
                                     "triangle {}: ({} {} {}) instead of ({} {} {})",
                                     reference_name, tri + 1, poly[0] + 1, poly[k] + 1,
                                     poly[k + 1] + 1, reference.faces(tri, 0) + 1,
                                     reference.faces(tri, 1) + 1, reference.faces(tri, 2) + 1),
                         path);
  }
}

}  // namespace

Vertices read_obj_frame(const std::string& path, const Mesh& reference,
                        const std::string& reference_name) {
  const std::string text = read_file_bytes(path);
  if (text.empty()) throw InvalidInput("empty file", path);
  const auto nv = reference.vertices.rows();
  Vertices V(nv, 3);
  Eigen::Index v = 0, tri = 0;
  std::size_t lineno = 0;
  std::vector<int> poly;
  const char* p = text.data();
  const char* end = p + text.size();
  auto where = [&] { return path + ":" + std::to_string(lineno); };
  for (const char* eol = p; p < end; p = eol + 1) {
    ++lineno;
    eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!eol) eol = end;
    const char* q = p;
    skip_blank(q, eol);
    if (q + 1 < eol && q[0] == 'v' && (q[1] == ' ' || q[1] == '\t')) {
      if (v >= nv)
        throw InvalidInput(fmt::format("more than the reference's {} vertices", nv), where());
      parse_vertex(q + 2, eol, V, v, path, lineno);
      ++v;
    } else if (q + 1 < eol && q[0] == 'f' && (q[1] == ' ' || q[1] == '\t')) {
      parse_face(q + 2, eol, v, poly, path, lineno);
      if (poly.size() >= 3) match_fan(poly, reference, reference_name, tri, path);
    }
  }
  if (v != nv)
    throw InvalidInput(
        fmt::format("has {} vertices but the reference {} has {}", v, reference_name, nv), path);
  if (tri != reference.faces.rows())
    throw InvalidInput(fmt::format("has {} triangles but the reference {} has {}", tri,
                                   reference_name, reference.faces.rows()),
                       path);
  return V;
}

void warn_about(const MeshReadReport& r, const std::string& path) {
  if (r.dropped_faces)
    log::warn("{}: {} faces with repeated corners were skipped by the reader", path,
              r.dropped_faces);
  if (r.degenerate_faces)
    log::warn("{}: {} degenerate (zero-area) faces; they get no weight", path, r.degenerate_faces);
  if (r.nonmanifold_edges)
    log::warn("{}: {} non-manifold edges (shared by more than two faces)", path,
              r.nonmanifold_edges);
  if (r.isolated_vertices)
    log::warn("{}: {} vertices belong to no face", path, r.isolated_vertices);
  if (r.polygons_triangulated)
    log::debug("{}: {} polygons fan-triangulated", path, r.polygons_triangulated);
}

void check_same_connectivity(const Mesh& reference, const std::string& reference_name,
                             const Mesh& frame, const std::string& frame_name) {
  if (frame.vertices.rows() != reference.vertices.rows())
    throw InvalidInput(
        fmt::format("has {} vertices but the reference {} has {}", frame.vertices.rows(),
                    reference_name, reference.vertices.rows()),
        frame_name);
  if (frame.faces.rows() != reference.faces.rows())
    throw InvalidInput(fmt::format("has {} triangles but the reference {} has {}",
                                   frame.faces.rows(), reference_name, reference.faces.rows()),
                       frame_name);
  for (Eigen::Index f = 0; f < frame.faces.rows(); ++f) {
    if (frame.faces.row(f) != reference.faces.row(f))
      throw InvalidInput(
          fmt::format("connectivity differs from the reference {} first at triangle {}: ({} {} {}) "
                      "instead of ({} {} {})",
                      reference_name, f + 1, frame.faces(f, 0) + 1, frame.faces(f, 1) + 1,
                      frame.faces(f, 2) + 1, reference.faces(f, 0) + 1, reference.faces(f, 1) + 1,
                      reference.faces(f, 2) + 1),
          frame_name);
  }
}

namespace {
using WriteMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMesh::DefaultTraitsDouble>;
}

MeshWriter::MeshWriter(const Faces& faces, std::size_t n_vertices)
    : faces_(faces), n_vertices_(n_vertices) {}
MeshWriter::~MeshWriter() = default;

void MeshWriter::write(const std::string& path, const Vertices& V) const {
  if (static_cast<std::size_t>(V.rows()) != n_vertices_)
    throw Error(
        fmt::format("internal: {} positions for a mesh of {} vertices", V.rows(), n_vertices_),
        path);
  std::string ext = lower_extension(path);
  if (ext != ".obj" && ext != ".off" && ext != ".ply")
    throw InvalidInput("unknown mesh format (expected .obj, .off or .ply)", path);
  // Written directly (OpenMesh's writers would need a manifold kernel, which drops faces that
  // are legal in our input); formats as OpenMesh writes them, full double precision.
  std::ofstream out(path, std::ios::binary);
  if (!out) throw IOError("cannot create file", path);
  fmt::memory_buffer b;
  auto fmt_vertex = [&](Eigen::Index i) {
    fmt::format_to(std::back_inserter(b), "{:.9g} {:.9g} {:.9g}", V(i, 0), V(i, 1), V(i, 2));
  };
  if (ext == ".obj") {
    fmt::format_to(std::back_inserter(b), "# deformflow\n");
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      fmt::format_to(std::back_inserter(b), "v ");
      fmt_vertex(i);
      b.push_back('\n');
    }
    for (Eigen::Index f = 0; f < faces_.rows(); ++f)
      fmt::format_to(std::back_inserter(b), "f {} {} {}\n", faces_(f, 0) + 1, faces_(f, 1) + 1,
                     faces_(f, 2) + 1);
  } else if (ext == ".off") {
    fmt::format_to(std::back_inserter(b), "OFF\n{} {} 0\n", V.rows(), faces_.rows());
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      fmt_vertex(i);
      b.push_back('\n');
    }
    for (Eigen::Index f = 0; f < faces_.rows(); ++f)
      fmt::format_to(std::back_inserter(b), "3 {} {} {}\n", faces_(f, 0), faces_(f, 1),
                     faces_(f, 2));
  } else {
    fmt::format_to(std::back_inserter(b),
                   "ply\n"
                   "format ascii 1.0\n"
                   "comment deformflow\n"
                   "element vertex {}\n"
                   "property double x\n"
                   "property double y\n"
                   "property double z\n"
                   "element face {}\n"
                   "property list uchar int vertex_indices\n"
                   "end_header\n",
                   V.rows(), faces_.rows());
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      fmt_vertex(i);
      b.push_back('\n');
    }
    for (Eigen::Index f = 0; f < faces_.rows(); ++f)
      fmt::format_to(std::back_inserter(b), "3 {} {} {}\n", faces_(f, 0), faces_(f, 1),
                     faces_(f, 2));
  }
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
  if (!out) throw IOError("cannot write file (disk full?)", path);
}

void write_mesh(const std::string& path, const Mesh& mesh) {
  MeshWriter(mesh.faces, static_cast<std::size_t>(mesh.vertices.rows())).write(path, mesh.vertices);
}

}  // namespace df::io
