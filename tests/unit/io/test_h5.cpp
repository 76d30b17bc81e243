#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "helpers.h"
#include "io/h5.h"
#include "io/zstd_filter.h"

using df::h5::File;

static std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST_CASE("h5: matrices, arrays, strings and attributes round-trip", "[io]") {
  df::test::TempDir tmp;
  Eigen::MatrixXd m = Eigen::MatrixXd::Random(50, 3);  // column-major input
  df::h5::Array<float> a{{4, 100, 9}, std::vector<float>(3600)};
  for (std::size_t i = 0; i < a.data.size(); ++i) a.data[i] = static_cast<float>(i) * 0.5f;
  {
    File f(tmp / "t.h5", File::Mode::create);
    f.write_matrix("/template/vertices", m);
    f.write("/features/normalized", a);
    f.write_strings("/frames/names", {"a", "bb", "ccc ü"});
    f.set_attr("/", "schema", "acap");
    f.set_attr("/", "schema_version", 3);
    f.set_attr("/normalization", "mode", "group");
    std::vector<double> mins{1, 2, 3};
    f.set_attr("/normalization", "min", std::span<const double>(mins));
    f.set_attr("/", "rate", 29.97);
    f.close();
  }
  File f(tmp / "t.h5", File::Mode::read);
  CHECK(f.read_matrix<double>("/template/vertices").isApprox(m, 0.0));
  auto b = f.read<float>("/features/normalized");
  CHECK(b.dims == a.dims);
  CHECK(b.data == a.data);
  CHECK(f.read_strings("/frames/names") == std::vector<std::string>{"a", "bb", "ccc ü"});
  CHECK(f.attr_string("/", "schema") == "acap");
  CHECK(f.attr_int("/", "schema_version") == 3);
  CHECK(f.attr_double("/", "rate") == 29.97);
  CHECK(f.attr_doubles("/normalization", "min") == std::vector<double>{1, 2, 3});
  CHECK(f.is_group("/template"));
  CHECK(f.is_dataset("/template/vertices"));
  CHECK_FALSE(f.exists("/nothing/here"));
  CHECK(f.children("/") ==
        std::vector<std::string>{"features", "frames", "normalization", "template"});
}

TEST_CASE("h5: large datasets are chunked, shuffled and zstd-compressed", "[io]") {
  df::test::TempDir tmp;
  df::h5::Array<float> a{{64, 1000, 3}, std::vector<float>(192000, 1.0f)};
  df::h5::Array<float> small{{2, 3}, std::vector<float>(6, 1.0f)};
  {
    File f(tmp / "c.h5", File::Mode::create);
    f.write("/big", a);
    f.write("/small", small);
  }
  File f(tmp / "c.h5", File::Mode::read);
  auto info = f.info("/big");
  CHECK(info.filters == std::vector<int>{H5Z_FILTER_SHUFFLE, df::h5::kZstdFilterId});
  CHECK(f.info("/small").filters.empty());
  CHECK(std::filesystem::file_size(tmp / "c.h5") < 192000 * 4 / 10);  // constant data compresses
  CHECK(f.read<float>("/big").data == a.data);
}

TEST_CASE("h5: row-wise streaming writes and reads", "[io]") {
  df::test::TempDir tmp;
  File f(tmp / "r.h5", File::Mode::create);
  f.create<double>("/x", {10, 4, 2});
  for (std::size_t t = 0; t < 10; t += 5) {
    std::vector<double> rows(5 * 8);
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<double>(t * 8 + i);
    f.write_rows<double>("/x", t, 5, rows.data());
  }
  std::vector<double> back(3 * 8);
  f.read_rows<double>("/x", 4, 3, back.data());
  CHECK(back.front() == 32.0);
  CHECK(back.back() == 55.0);
  CHECK_THROWS(f.read_rows<double>("/x", 9, 2, back.data()));
}

TEST_CASE("h5: identical data gives identical bytes (no timestamps)", "[io]") {
  df::test::TempDir tmp;
  for (const char* name : {"a.h5", "b.h5"}) {
    File f(tmp / name, File::Mode::create);
    f.write_matrix("/g/m", Eigen::MatrixXf::Constant(300, 40, 2.5f));
    f.write_strings("/g/s", {"x", "y"});
    f.set_attr("/g", "note", "same");
    f.close();
    sleep(1);
  }
  CHECK(slurp(tmp / "a.h5") == slurp(tmp / "b.h5"));
}

TEST_CASE("h5: errors name the file and the object", "[io]") {
  df::test::TempDir tmp;
  CHECK_THAT(df::test::error_message([&] { File(tmp / "missing.h5", File::Mode::read); }),
             Catch::Contains("no such file") && Catch::Contains("missing.h5"));
  df::test::write_text(tmp / "text.h5", "just text\n");
  CHECK_THROWS_WITH(File(tmp / "text.h5", File::Mode::read), Catch::Contains("not an HDF5 file"));
  {
    File f(tmp / "e.h5", File::Mode::create);
    f.write_matrix("/a", Eigen::MatrixXd::Zero(2, 2));
  }
  File f(tmp / "e.h5", File::Mode::read);
  try {
    f.read<double>("/frames/positions");
    FAIL("expected an error");
  } catch (const df::Error& e) {
    CHECK(e.message() == "missing dataset (" + (tmp / "e.h5") + ":/frames/positions)");
  }
  CHECK_THROWS_WITH(f.attr_string("/a", "nope"), Catch::Contains("missing attribute 'nope'"));
  CHECK_THROWS_WITH(f.read_strings("/a"), Catch::Contains("not of strings"));
}

TEST_CASE("h5: parallel chunk I/O is byte-compatible with HDF5's filter pipeline", "[io]") {
  df::test::TempDir tmp;
  // 37 rows of 5000 doubles: 40 KB rows, 26 rows per 1 MiB chunk, a partial edge chunk.
  const std::size_t rows = 37, cols = 5000;
  std::vector<double> data(rows * cols);
  for (std::size_t i = 0; i < data.size(); ++i)
    data[i] = std::sin(0.001 * static_cast<double>(i)) * 1e3;
  {
    File f(tmp / "p.h5", File::Mode::create);
    f.write<double>("/pipeline", data, {rows, cols});  // H5Dwrite through the filters
    f.create<double>("/direct", {rows, cols});
    f.write_rows<double>("/direct", 0, 26, data.data());  // whole chunk(s): direct path
    f.write_rows<double>("/direct", 26, 11, data.data() + 26 * cols);  // the edge chunk
    f.create<double>("/blocks", {rows, cols});
    f.write_rows<double>("/blocks", 0, rows, data.data());  // two chunks at once, in parallel
  }
  File f(tmp / "p.h5", File::Mode::read);
  CHECK(f.info("/blocks").filters == std::vector<int>{H5Z_FILTER_SHUFFLE, df::h5::kZstdFilterId});
  CHECK(f.read<double>("/direct").data == data);  // direct-written chunks decode via HDF5
  CHECK(f.read<double>("/blocks").data == data);
  std::vector<double> back(rows * cols);
  f.read_rows<double>("/pipeline", 0, rows, back.data());  // pipeline-written, read directly
  CHECK(back == data);
  std::vector<float> as_float(rows * cols);  // type conversion falls back to H5Dread
  f.read_rows<float>("/blocks", 0, rows, as_float.data());
  CHECK(as_float[12345] == static_cast<float>(data[12345]));
}

TEST_CASE("h5: unaligned row ranges mix pipeline head/tail with parallel whole chunks", "[io]") {
  df::test::TempDir tmp;
  const std::size_t rows = 200, cols = 5000;  // 26 rows per chunk
  std::vector<double> data(rows * cols);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<double>(i % 9973) * 0.25;
  {
    File f(tmp / "u.h5", File::Mode::create);
    f.create<double>("/x", {rows, cols});
    f.write_rows<double>("/x", 0, 10, data.data());                 // head only
    f.write_rows<double>("/x", 10, 180, data.data() + 10 * cols);   // 16 + 6 chunks + 8
    f.write_rows<double>("/x", 190, 10, data.data() + 190 * cols);  // tail to the end
  }
  File f(tmp / "u.h5", File::Mode::read);
  CHECK(f.read<double>("/x").data == data);
  for (auto [first, count] :
       {std::pair<std::size_t, std::size_t>{0, 200}, {5, 190}, {27, 100}, {150, 50}}) {
    std::vector<double> back(count * cols);
    f.read_rows<double>("/x", first, count, back.data());
    REQUIRE(std::equal(back.begin(), back.end(),
                       data.begin() + static_cast<std::ptrdiff_t>(first * cols)));
  }
}
