#include "core/word_lines.h"

#include <fstream>
#include <sstream>

#include "core/error.h"

namespace df {

std::vector<WordLine> read_word_lines(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw IOError("cannot read " + what, path);
  std::vector<WordLine> lines;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line.substr(0, line.find('#')));
    WordLine l{number, {}};
    for (std::string word; words >> word;) l.words.push_back(std::move(word));
    if (!l.words.empty()) lines.push_back(std::move(l));
  }
  return lines;
}

}  // namespace df
