#include "diagnostics/snapshot_fields.hpp"

namespace capsim {

void add_membrane_fields(const Membrane& membrane, int num_capsules,
                         const std::vector<Vec3>& x, SnapshotFrame& frame) {
  const Topology& topo = membrane.topology();
  const int nn = topo.num_nodes;
  std::vector<double> weight(x.size(), 0.0);
  frame.tension_max.assign(x.size(), 0.0);
  frame.tension_min.assign(x.size(), 0.0);
  for (int c = 0; c < num_capsules; ++c) {
    const std::vector<ElementTensions> t = membrane.element_tensions(&x[c * nn]);
    for (size_t e = 0; e < t.size(); ++e) {
      const double w = membrane.references()[e].area0;
      for (int node : topo.triangles[e]) {
        frame.tension_max[c * nn + node] += w * t[e].t1;
        frame.tension_min[c * nn + node] += w * t[e].t2;
        weight[c * nn + node] += w;
      }
      frame.area_dilatation.push_back(t[e].dilatation);
      frame.element_tension_max.push_back(t[e].t1);
      frame.element_tension_min.push_back(t[e].t2);
    }
  }
  for (size_t i = 0; i < x.size(); ++i) {
    frame.tension_max[i] /= weight[i];
    frame.tension_min[i] /= weight[i];
  }
}

} // namespace capsim
