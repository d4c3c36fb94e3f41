#pragma once
#include "stokes/periodic_cells.hpp"

#include <algorithm>
#include <vector>

namespace capsim {

// Triangles by centroid for the search of each node's near triangles, which must reach
// quad.far_ratio times a triangle's diameter. One reach for all, set by the largest
// triangle, fails when a capsule is stretched into a thread (phi 0.4, Ca 0.6): its few
// long triangles made every node scan most of the box, and the near search took 85 % of
// a step. So triangles more than twice the mean diameter get cells of their own with
// their longer reach; the rest keep a reach set by the mean.
class NearTriangleCells {
public:
  NearTriangleCells(const ShearedLattice& g, const std::vector<Vec3>& centroids,
                    const std::vector<double>& diameters, double far_ratio) {
    double mean = 0, largest = 0;
    for (double d : diameters)
      mean += d / double(diameters.size()), largest = std::max(largest, d);
    const double split = std::min(largest, 2.0 * mean);
    std::vector<int> ids[2];
    std::vector<Vec3> points[2];
    for (int t = 0; t < int(diameters.size()); ++t) {
      const int big = diameters[t] > split;
      ids[big].push_back(t);
      points[big].push_back(centroids[t]);
    }
    for (int big = 0; big < 2; ++big)
      if (!ids[big].empty())
        groups_.push_back({ids[big], PeriodicCells(g, far_ratio * (big ? largest : split),
                                                   points[big])});
  }

  // Calls visit(triangle, image of its centroid) for every triangle whose centroid
  // image lies within reach of x (and some more, as PeriodicCells does).
  template <class Visit> void for_neighbours(Vec3 x, Visit visit) const {
    for (const Group& group : groups_)
      group.cells.for_neighbours(x,
                                 [&](int j, Vec3 image) { visit(group.ids[j], image); });
  }

private:
  struct Group {
    std::vector<int> ids; // triangle of each point of the cells
    PeriodicCells cells;
  };
  std::vector<Group> groups_;
};

} // namespace capsim
