// h5check: validate deformflow HDF5 files against the schema they declare and summarise them.
#include "core/error.h"
#include "core/tool.h"
#include "io/inspect.h"
#include "io/schema.h"

int main(int argc, char** argv) {
  df::Tool tool("h5check",
                "Validate deformflow HDF5 files (acap, skeleton, model and components kinds)\n"
                "against the schema each declares, and print a summary per file: kind,\n"
                "dimension sizes, datasets with type, shape and compression, and history.\n"
                "Exit status 0 if every file is valid, 1 otherwise (each problem on stderr).");
  std::vector<std::string> files;
  df::io::InspectOptions opt;
  bool no_history = false;
  tool.app().add_option("FILE", files, "HDF5 files to check")->required();
  tool.app().add_option("--kind", opt.expected_kind,
                        "Require this file kind (e.g. acap, skeleton)");
  tool.app().add_flag("--structure-only", opt.structure_only,
                      "Check groups, types and shapes only; do not read the data (faster)");
  tool.app().add_flag("--no-history", no_history, "Do not print the history lines");
  tool.footer(
      "Schemas: schemas/<kind>.json in the source tree (embedded in this binary).\n"
      "Example: h5check out/finger.h5 && echo valid");
  return tool.run(argc, argv, [&] {
    opt.show_history = !no_history;
    if (!opt.expected_kind.empty()) df::io::schema(opt.expected_kind);  // unknown kind -> error
    int bad = df::io::inspect_files(files, opt);
    if (bad)
      throw df::InvalidInput(std::to_string(bad) + " of " + std::to_string(files.size()) +
                             " files invalid");
  });
}
