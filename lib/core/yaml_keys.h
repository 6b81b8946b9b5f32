#pragma once
// YAML parsers keep the last of two equal keys without a word, so a config
// with `n_features: 500` twice silently uses one of them. This scans the text
// of a file for a key repeated within one block mapping, before it is parsed.
#include <cstddef>
#include <istream>
#include <string>

namespace dynslam {

struct DuplicateKey {
  std::string key;
  std::size_t line = 0;        ///< 1-based line of the repetition
  std::size_t first_line = 0;  ///< where the key first appeared
};

/// First key repeated in the same block mapping (indentation-based: flow
/// mappings `{a: 1}` and block scalars are not looked into). line 0: none.
DuplicateKey findDuplicateKey(std::istream& yaml_text);

}  // namespace dynslam
