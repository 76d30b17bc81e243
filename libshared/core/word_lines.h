// The words of a small text file's lines, as the tools' list files are written (handles, labels,
// joint layouts): '#' starts a comment, blank lines are skipped, words are separated by blanks,
// and each line keeps its number for messages (file:line).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace df {

struct WordLine {
  std::size_t number = 0;  ///< 1-based line number in the file
  std::vector<std::string> words;
};

/// The file's lines that have words. IOError "cannot read <what>" naming `path` when it cannot be
/// opened.
std::vector<WordLine> read_word_lines(const std::string& path, const std::string& what);

}  // namespace df
