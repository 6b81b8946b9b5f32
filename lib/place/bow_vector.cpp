#include "place/bow_vector.h"

#include <algorithm>

namespace dynslam {

namespace {
/// Calls fn(entry_a, entry_b) for every word present in both sorted vectors.
template <typename Fn>
void forSharedWords(const BowVector& a, const BowVector& b, Fn fn) {
  auto ia = a.begin(), ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->word < ib->word) {
      ++ia;
    } else if (ib->word < ia->word) {
      ++ib;
    } else {
      fn(*ia, *ib);
      ++ia;
      ++ib;
    }
  }
}
}  // namespace

double l1Score(const BowVector& a, const BowVector& b) {
  double s = 0;
  forSharedWords(a, b,
                 [&](const BowEntry& x, const BowEntry& y) { s += std::min(x.weight, y.weight); });
  return s;
}

int commonWords(const BowVector& a, const BowVector& b) {
  int n = 0;
  forSharedWords(a, b, [&](const BowEntry&, const BowEntry&) { ++n; });
  return n;
}

}  // namespace dynslam
