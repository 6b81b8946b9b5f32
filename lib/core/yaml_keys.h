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

/// First key repeated in the same block mapping (indentation-based), or in
/// one flow mapping `{a: 1, a: 2}` written on one line (then line and
/// first_line are that line); block scalars are not looked into. line 0: none.
DuplicateKey findDuplicateKey(std::istream& yaml_text);

/// The 1-based line that holds the dotted key ("orb.n_features"), by the
/// block layout's indentation, so that the same key in another section is
/// not taken; 0 if no line does (flow mappings are not looked into). Errors
/// about a key's value name it.
std::size_t findKeyLine(std::istream& yaml_text, const std::string& dotted_key);

}  // namespace dynslam
