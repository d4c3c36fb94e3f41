#pragma once
#include "stokes/cells/periodic_cells.hpp"
#include "stokes/quadrature/near_triangles.hpp"

#include <vector>

namespace capsim {

// Triangles by centroid for the search of each node's near triangles in the periodic
// box, in the two groups of split_by_diameter, each with cells of its own reach.
class NearTriangleCells {
public:
  NearTriangleCells(const ShearedLattice& g, const std::vector<Vec3>& centroids,
                    const std::vector<double>& diameters, double far_ratio) {
    const DiameterGroups split = split_by_diameter(diameters, far_ratio);
    for (int big = 0; big < 2; ++big) {
      if (split.ids[big].empty())
        continue;
      std::vector<Vec3> points;
      for (int t : split.ids[big])
        points.push_back(centroids[t]);
      // Cells two thirds of the reach wide: the triangles are sparse (about one per cell
      // a third of the reach wide), so fewer cells, not a tighter stencil, is what pays:
      // the stage took 14-23 % less (docs/performance.md).
      groups_.push_back(
          {split.ids[big],
           PeriodicCells(g, split.reach[big], points, PeriodicCells::Index::table, 1.5)});
    }
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
