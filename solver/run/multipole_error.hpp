#pragma once
// `capsim multipole-error`: the data of the paper's figure 1. For the capsule state in a
// run's checkpoint, the relative error (eq. 3.11) of the P-patch coarse-grained velocity
// (eq. 3.10) against the fine quadrature (eq. 3.9) at distance r/a from the centroid
// along the flow (x), vorticity (z) and gradient (y) directions, and their mean.
#include <string>
#include <vector>

namespace capsim {

struct MultipoleErrorRow {
  double ca = 0;      // the run's, so that the table names its own capsule
  int mesh_level = 0; // (figure 1 reads them from here, not from a file name)
  int patches = 0;
  double r = 0;
  double error_flow = 0, error_vorticity = 0, error_gradient = 0, error_mean = 0;
};

std::vector<MultipoleErrorRow> multipole_error(const std::string& run_dir,
                                               const std::vector<int>& patch_counts,
                                               const std::vector<double>& distances);

std::string multipole_error_csv(const std::vector<MultipoleErrorRow>& rows);

} // namespace capsim
