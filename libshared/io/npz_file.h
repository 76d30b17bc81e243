// NumPy's .npz archives (np.savez, np.savez_compressed): a zip file of .npy arrays, stored or
// deflated, with zip64 records as numpy writes them. Read with minizip (Debian's libminizip, which
// assimp already pulls in) from bytes in memory, every member parsed as a .npy (npy_file.h).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "io/npy_file.h"

namespace df::io {

struct NpzMember {
  std::string name;  ///< the member's file name without ".npy" (np.savez's keyword)
  NpyArray array;
};

/// The archive's members in the archive's order. InvalidInput (naming `name`) when the bytes are
/// not a zip archive, a member is not a .npy array, or its data is damaged (CRC).
std::vector<NpzMember> parse_npz(std::string_view bytes, const std::string& name);
/// The same from a file (IOError when it cannot be read).
std::vector<NpzMember> read_npz(const std::string& path);

}  // namespace df::io
