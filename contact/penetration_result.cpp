#include "contact/penetration_result.h"

#include <algorithm>

namespace hipfai::contact {

void sort_by_mobile_vertex(std::vector<PenetrationPair>& pairs) {
  std::sort(pairs.begin(), pairs.end(), [](const PenetrationPair& a, const PenetrationPair& b) {
    return a.mobile_vertex < b.mobile_vertex;
  });
}

}  // namespace hipfai::contact
