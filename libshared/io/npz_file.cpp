#include "io/npz_file.h"

#include <fmt/format.h>
#include <unzip.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "core/error.h"
#include "io/file_bytes.h"

namespace df::io {
namespace {

// minizip's file functions over bytes in memory (the archive is read whole first, as .npy files
// are: a fuzzer then reaches the same code with no file).
struct MemoryStream {
  std::string_view bytes;
  std::size_t at = 0;
};

voidpf ZCALLBACK memory_open(voidpf opaque, const void*, int mode) {
  if ((mode & ZLIB_FILEFUNC_MODE_READWRITEFILTER) != ZLIB_FILEFUNC_MODE_READ) return nullptr;
  return opaque;
}

uLong ZCALLBACK memory_read(voidpf, voidpf stream, void* buf, uLong size) {
  auto& s = *static_cast<MemoryStream*>(stream);
  const std::size_t n = std::min<std::size_t>(size, s.bytes.size() - s.at);
  std::memcpy(buf, s.bytes.data() + s.at, n);
  s.at += n;
  return static_cast<uLong>(n);
}

uLong ZCALLBACK memory_write(voidpf, voidpf, const void*, uLong) {
  return 0;
}

ZPOS64_T ZCALLBACK memory_tell(voidpf, voidpf stream) {
  return static_cast<MemoryStream*>(stream)->at;
}

long ZCALLBACK memory_seek(voidpf, voidpf stream, ZPOS64_T offset, int origin) {
  auto& s = *static_cast<MemoryStream*>(stream);
  std::uint64_t base = 0;
  if (origin == ZLIB_FILEFUNC_SEEK_CUR) base = s.at;
  if (origin == ZLIB_FILEFUNC_SEEK_END) base = s.bytes.size();
  if (offset > s.bytes.size() - std::min<std::uint64_t>(base, s.bytes.size()) ||
      base > s.bytes.size())
    return -1;
  s.at = static_cast<std::size_t>(base + offset);
  return 0;
}

int ZCALLBACK memory_close(voidpf, voidpf) {
  return 0;
}

int ZCALLBACK memory_error(voidpf, voidpf) {
  return 0;
}

struct CloseArchive {
  void operator()(void* f) const { unzClose(f); }
};
using Archive = std::unique_ptr<void, CloseArchive>;

// The current member's bytes (at most its declared size; the CRC checked on close).
std::string member_bytes(unzFile zip, const unz_file_info64& info, const std::string& where) {
  if (unzOpenCurrentFile(zip) != UNZ_OK)
    throw InvalidInput(
        "a member that cannot be opened (an unknown compression or damaged "
        "header)",
        where);
  std::string out;
  char chunk[1 << 16];
  int n = 0;
  while ((n = unzReadCurrentFile(zip, chunk, sizeof chunk)) > 0) {
    if (out.size() + static_cast<std::size_t>(n) > info.uncompressed_size) {
      unzCloseCurrentFile(zip);
      throw InvalidInput("a member longer than its declared size", where);
    }
    out.append(chunk, static_cast<std::size_t>(n));
  }
  const int closed = unzCloseCurrentFile(zip);
  if (n < 0) throw InvalidInput(fmt::format("a damaged member (zip error {})", n), where);
  if (closed == UNZ_CRCERROR) throw InvalidInput("a damaged member (CRC mismatch)", where);
  if (out.size() != info.uncompressed_size)
    throw InvalidInput(
        fmt::format("a member of {} bytes, {} declared", out.size(), info.uncompressed_size),
        where);
  return out;
}

}  // namespace

std::vector<NpzMember> parse_npz(std::string_view bytes, const std::string& name) {
  MemoryStream stream{bytes};
  zlib_filefunc64_def io{};
  io.zopen64_file = memory_open;
  io.zread_file = memory_read;
  io.zwrite_file = memory_write;
  io.ztell64_file = memory_tell;
  io.zseek64_file = memory_seek;
  io.zclose_file = memory_close;
  io.zerror_file = memory_error;
  io.opaque = &stream;
  const Archive zip(unzOpen2_64(name.c_str(), &io));
  if (!zip) throw InvalidInput("not a .npz archive (no zip directory)", name);
  std::vector<NpzMember> members;
  for (int r = unzGoToFirstFile(zip.get()); r != UNZ_END_OF_LIST_OF_FILE;
       r = unzGoToNextFile(zip.get())) {
    if (r != UNZ_OK) throw InvalidInput("a damaged zip directory", name);
    unz_file_info64 info{};
    char file_name[1024] = {};
    if (unzGetCurrentFileInfo64(zip.get(), &info, file_name, sizeof file_name - 1, nullptr, 0,
                                nullptr, 0) != UNZ_OK)
      throw InvalidInput("a damaged zip directory entry", name);
    std::string member = file_name;
    const std::string where = fmt::format("{} ({})", name, member);
    if (member.size() < 5 || member.substr(member.size() - 4) != ".npy")
      throw InvalidInput("a member that is not a .npy array", where);
    NpyArray a = parse_npy(member_bytes(zip.get(), info, where), where);
    members.push_back({member.substr(0, member.size() - 4), std::move(a)});
  }
  if (members.empty()) throw InvalidInput("an empty .npz archive", name);
  return members;
}

std::vector<NpzMember> read_npz(const std::string& path) {
  return parse_npz(read_file_bytes(path), path);
}

}  // namespace df::io
