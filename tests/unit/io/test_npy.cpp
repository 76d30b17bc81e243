#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "core/error.h"
#include "io/npy_file.h"
#include "io/npz_file.h"

using namespace df;

namespace {

// A .npy file of format version `major` with header dictionary `dict` and raw data `data`.
std::string npy(int major, const std::string& dict, const std::string& data) {
  std::string h = dict;
  const std::size_t prefix = major == 1 ? 10 : 12;
  while ((prefix + h.size() + 1) % 64) h += ' ';
  h += '\n';
  std::string out = std::string("\x93NUMPY", 6) + static_cast<char>(major) + '\0';
  const auto n = static_cast<std::uint32_t>(h.size());
  out.append(reinterpret_cast<const char*>(&n), major == 1 ? 2 : 4);
  return out + h + data;
}

template <class T>
std::string raw(std::initializer_list<T> v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.begin(), s.size());
  return s;
}

}  // namespace

TEST_CASE("npy: C and Fortran order, the number types, versions 1 and 2", "[io][npy]") {
  // [[1, 2, 3], [4, 5, 6]] stored row by row, and column by column
  const auto c = io::parse_npy(npy(1, "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                                   raw<float>({1, 2, 3, 4, 5, 6})),
                               "c");
  REQUIRE(c.shape == std::vector<std::int64_t>{2, 3});
  REQUIRE(c.values == std::vector<double>{1, 2, 3, 4, 5, 6});
  const auto f = io::parse_npy(npy(2, "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
                                   raw<double>({1, 4, 2, 5, 3, 6})),
                               "f");
  REQUIRE(f.values == c.values);
  // three dimensions in Fortran order: element (i, j, k) at i + 2 j + 4 k
  std::vector<double> want, stored(8);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        want.push_back(100 * i + 10 * j + k);
        stored[static_cast<std::size_t>(i + 2 * j + 4 * k)] = 100 * i + 10 * j + k;
      }
  std::string data(8 * sizeof(double), '\0');
  std::memcpy(data.data(), stored.data(), data.size());
  REQUIRE(io::parse_npy(npy(1, "{'shape': (2, 2, 2), 'fortran_order': True, 'descr': '<f8'}", data),
                        "f3")
              .values == want);
  REQUIRE(io::parse_npy(npy(1, "{'descr': '<i8', 'fortran_order': False, 'shape': (3,), }",
                            raw<std::int64_t>({-7, 0, 1LL << 40})),
                        "i8")
              .values == std::vector<double>{-7, 0, 1099511627776.0});
  REQUIRE(io::parse_npy(npy(1, "{'descr': '<i4', 'fortran_order': False, 'shape': (2,), }",
                            raw<std::int32_t>({-3, 9})),
                        "i4")
              .values == std::vector<double>{-3, 9});
}

TEST_CASE("npy: what is not read is an InvalidInput naming the file", "[io][npy]") {
  const std::string ok = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
  REQUIRE_THROWS_WITH(io::parse_npy("NUMPY", "x.npy"), Catch::Contains("no \\x93NUMPY magic"));
  REQUIRE_THROWS_AS(io::parse_npy(npy(1, ok, raw<float>({1, 2, 3})), "x.npy"), InvalidInput);
  REQUIRE_THROWS_WITH(io::parse_npy(npy(1, ok, raw<float>({1, 2, 3})), "x.npy"),
                      Catch::Contains("truncated .npy array: 12 bytes of data for 6 elements"));
  REQUIRE_THROWS_WITH(
      io::parse_npy(
          npy(1, "{'descr': '>f4', 'fortran_order': False, 'shape': (1,), }", raw<float>({1})),
          "x.npy"),
      Catch::Contains("dtype '>f4'"));
  REQUIRE_THROWS_WITH(
      io::parse_npy(
          npy(1, "{'descr': '|S3', 'fortran_order': False, 'shape': (1,), }", std::string(12, 'a')),
          "x.npy"),
      Catch::Contains("dtype '|S3'"));
  REQUIRE_THROWS_WITH(
      io::parse_npy(npy(1, "{'descr': '<f4', 'shape': (1,), }", raw<float>({1})), "x.npy"),
      Catch::Contains("without 'fortran_order'"));
  REQUIRE_THROWS_WITH(io::parse_npy(npy(7, ok, ""), "x.npy"), Catch::Contains("version 7"));
}

TEST_CASE("npy: unicode strings (class labels) as UTF-8", "[io][npy]") {
  // ['walk', 'héllo'] as '<U5': five UTF-32LE code units each, NUL-padded
  const auto list =
      io::parse_npy(npy(1, "{'descr': '<U5', 'fortran_order': False, 'shape': (2,), }",
                        raw<std::uint32_t>({'w', 'a', 'l', 'k', 0, 'h', 0xE9, 'l', 'l', 'o'})),
                    "list");
  CHECK(list.is_text());
  CHECK(list.values.empty());
  CHECK(list.strings == std::vector<std::string>{"walk", "h\xC3\xA9llo"});
  const auto scalar =
      io::parse_npy(npy(1, "{'descr': '<U3', 'fortran_order': False, 'shape': (), }",
                        raw<std::uint32_t>({'n', 'o', 'd'})),
                    "scalar");
  CHECK(scalar.strings == std::vector<std::string>{"nod"});
  CHECK_THROWS_AS(io::parse_npy(npy(1, "{'descr': '<U3', 'fortran_order': False, 'shape': (2,), }",
                                    raw<std::uint32_t>({'n', 'o', 'd'})),
                                "short"),
                  InvalidInput);  // 2 strings, data for 1
  CHECK_THROWS_AS(io::parse_npy(npy(1, "{'descr': '<U1', 'fortran_order': False, 'shape': (1,), }",
                                    raw<std::uint32_t>({0xD800})),
                                "surrogate"),
                  InvalidInput);
  CHECK_THROWS_AS(
      io::parse_npy(npy(1, "{'descr': '<U2', 'fortran_order': False, 'shape': (1, 1), }",
                        raw<std::uint32_t>({'a', 'b'})),
                    "2-D"),
      InvalidInput);
}

TEST_CASE("npz: what is not a zip archive of .npy members is refused", "[io][npy]") {
  CHECK_THROWS_WITH(io::parse_npz("", "empty.npz"), Catch::Contains("not a .npz archive"));
  CHECK_THROWS_WITH(io::parse_npz("PK\x03\x04 and then nothing", "cut.npz"),
                    Catch::Contains("not a .npz archive"));
  // An empty zip archive (the end-of-central-directory record alone): minizip opens none
  const std::string empty_zip("PK\x05\x06\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 22);
  CHECK_THROWS_AS(io::parse_npz(empty_zip, "none.npz"), InvalidInput);
}
