#pragma once
// MRPT's YAML reader builds its tree by recursion, one call per nested list
// or map (keys included), and the tree is destroyed the same way: a document
// nested thousands deep overflows the stack however the nesting is written
// (flow brackets, indentation, compact "- - -" or "? ? ?", on one line or
// spread over many). Reading the characters cannot tell all of those apart,
// so the text is first walked as libyaml's event stream, whose parser keeps
// its state on the heap, and the structure MRPT cannot take is refused there.
#include <string>

namespace dynslam {

/// Lists and maps nested deeper than this are refused. dynslam's own YAML
/// files nest at most four levels; MRPT's recursion overflowed the stack
/// near 10,000 levels, so the bound is far from both.
constexpr int kMaxYamlNesting = 64;

/// Throws InputError(path, LINE, ...) at the first line where `text`
///  - is not YAML (libyaml's problem, so MRPT never reads text past a point
///    the check did not),
///  - nests lists or maps more than kMaxYamlNesting deep,
///  - starts a second document (MRPT reads the first only),
///  - has an anchor or alias (& and *: MRPT asserts on them).
void checkYamlStructure(const std::string& path, const std::string& text);

}  // namespace dynslam
