#include "membrane/compression.hpp"

#include <algorithm>

namespace capsim {
namespace {

void add(Compression& c, const ElementTensions& t) {
  c.min_tension = c.of == 0 ? t.t2 : std::min(c.min_tension, t.t2);
  ++c.of;
  if (t.t2 < kCompressedTension)
    ++c.elements;
}

} // namespace

Compression compression(const std::vector<ElementTensions>& tensions) {
  Compression c;
  for (const ElementTensions& t : tensions)
    add(c, t);
  return c;
}

Compression compression_near(const Topology& topo,
                             const std::vector<ElementTensions>& tensions, int triangle) {
  const auto& centre = topo.triangles[triangle];
  auto shares_a_node = [&](const std::array<int, 3>& t) {
    for (int a : t)
      if (std::find(centre.begin(), centre.end(), a) != centre.end())
        return true;
    return false;
  };
  Compression c;
  for (size_t e = 0; e < topo.triangles.size(); ++e)
    if (shares_a_node(topo.triangles[e]))
      add(c, tensions[e]);
  return c;
}

} // namespace capsim
