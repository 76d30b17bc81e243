// Structure checks of mesh files before OpenMesh reads them. OpenMesh's readers trust their
// input: an OBJ face naming vertex 0 trips an assertion (the process aborts), a PLY header
// with a second `format` line crashes its header parser, an OFF header promising 400 million
// vertices keeps it busy for minutes (all found by fuzzing, tests/fuzz). These checks walk the
// file once and refuse such input with an InvalidInput naming the file and line, so that the
// readers only ever see files whose counts, indices and record sizes add up:
//   OBJ  every face has >= 3 corners whose vertex (and texture / normal) indices name an
//        element defined before it (1-based, or negative = relative);
//   OFF  plain OFF (the keyword alone on its line) whose counts fit the file; ASCII: exactly
//        x y z per vertex line and n >= 3 plus n indices below the vertex count per face line
//        (OpenMesh reads a token stream: one token too many shifts every later record);
//   PLY  a well-formed header (one format line, known property types, end_header), and every
//        record of every element inside the file (ASCII: one record per line with exactly the
//        tokens its properties and list counts call for; binary: list counts within the file);
//   and in every text coordinate: no NaN/Inf.
#pragma once

#include <cstddef>
#include <string>

namespace df::io {

/// What the pass sees that OpenMesh's OBJ reader hides: how many vertex and face lines there
/// are (it drops unreadable vertices and faces with repeated corners).
struct MeshTextScan {
  std::size_t obj_vertex_lines = 0, obj_face_lines = 0;
};

/// Throws InvalidInput (file:line) when the file's structure does not add up or a coordinate is
/// NaN/Inf; `ext` is the lower-case extension (".obj", ".off" or ".ply").
MeshTextScan check_mesh_structure(const std::string& path, const std::string& ext);

}  // namespace df::io
