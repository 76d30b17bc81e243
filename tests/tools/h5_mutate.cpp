// Test driver (not installed): copies a valid acap file and plants one schema violation, for
// the h5check golden cases (each class of violation h5check reports).
#include <hdf5.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <map>

#include "core/error.h"
#include "core/tool.h"
#include "io/h5.h"

namespace {

using df::h5::File;

const std::map<std::string, std::function<void(File&)>>& mutations() {
  static const std::map<std::string, std::function<void(File&)>> m = {
      {"kind", [](File& f) { f.set_attr("/", "schema", "skeleton"); }},
      {"version", [](File& f) { f.set_attr("/", "schema_version", 99); }},
      {"shape", [](File& f) { f.write_matrix("/template/vertices", Eigen::MatrixXd::Zero(4, 2)); }},
      {"dtype",
       [](File& f) {
         auto v = f.read_matrix<double>("/template/vertices");
         f.write_matrix("/template/vertices", v.cast<float>().eval());
       }},
      {"rank",
       [](File& f) {
         auto p = f.read<float>("/frames/positions");
         f.write<float>("/frames/positions", p.data, {p.dims[0], p.dims[1] * p.dims[2]});
       }},
      {"nan",
       [](File& f) {
         auto p = f.read<float>("/frames/positions");
         p.data[p.size() / 2] = std::numeric_limits<float>::quiet_NaN();
         f.write("/frames/positions", p);
       }},
      {"index",
       [](File& f) {
         auto faces = f.read_matrix<std::int32_t>("/template/faces");
         faces(faces.rows() - 1, 2) = 1000;
         f.write_matrix("/template/faces", faces);
       }},
      {"offsets",
       [](File& f) {
         auto o = f.read<std::int64_t>("/sequences/offsets");
         o.data.back() -= 1;
         f.write("/sequences/offsets", o);
       }},
      {"missing-dataset", [](File& f) { H5Ldelete(f.id(), "/frames/names", H5P_DEFAULT); }},
      {"missing-attribute", [](File& f) { H5Adelete(f.id(), "history"); }},
      {"unstored-huge",  // 2^30 frames declared, never written
       [](File& f) {
         auto p = f.info("/frames/positions");
         H5Ldelete(f.id(), "/frames/positions", H5P_DEFAULT);
         f.create<float>("/frames/positions", {std::size_t(1) << 30, p.dims[1], p.dims[2]});
       }},
      {"attribute-value",
       [](File& f) {
         f.create_groups("/normalization");
         f.set_attr("/normalization", "mode", "sideways");
       }},
  };
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  df::Tool tool("h5_mutate", "Copy an acap file and plant one schema violation (test driver).");
  std::string input, output, mutation;
  tool.app().add_option("INPUT", input)->required();
  tool.app().add_option("OUTPUT", output)->required();
  tool.app().add_option("MUTATION", mutation)->required();
  return tool.run(argc, argv, [&] {
    auto it = mutations().find(mutation);
    if (it == mutations().end()) throw df::UsageError("unknown mutation '" + mutation + "'");
    std::filesystem::copy_file(input, output, std::filesystem::copy_options::overwrite_existing);
    File f(output, File::Mode::read_write);
    it->second(f);
    f.close();
  });
}
