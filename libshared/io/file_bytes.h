#pragma once
// The whole of a file in memory, in one read: the mesh and MD2 readers' common first step.
#include <string>

namespace df::io {

// The file's bytes. Throws IOError ("no such file" / "cannot read file") naming the path.
std::string read_file_bytes(const std::string& path);

}  // namespace df::io
