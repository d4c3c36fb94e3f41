#pragma once
// The real-space part of the periodic double layer's Ewald sum at one target: the
// stresslet pairs within r_cut gathered into a contiguous buffer (structure of arrays),
// then summed in one vectorised loop, as the single layer's screened_sum
// (real_space_sum.hpp).
#include "common/vec3.hpp"
#include "stokes/ewald/pair_buffer.hpp"

#include <cstddef>
#include <vector>

namespace capsim {

// Separations r and the symmetric parts d = sym(u a^T) (xx, yy, zz, xy, xz, yz) of the
// pairs of one target.
struct StressletPairBuffer {
  std::vector<double> r[3], d[6];
  size_t n = 0;

  // Room for at least m pairs (the contents up to n are kept).
  void reserve(size_t m) {
    if (m > r[0].size()) {
      for (auto& v : r)
        v.resize(m);
      for (auto& v : d)
        v.resize(m);
    }
  }
  // Room for at least m pairs, doubling (PeriodicCells::gather_within).
  void make_room(size_t m) {
    if (m > r[0].size())
      reserve(2 * m);
  }
};

// sum_j u_j,i T^R_ijk(r_j) a_j,k (ewald_stresslet.hpp (2)) over the buffer's pairs: the
// vectorised inner loop (AVX-512/AVX2 clones).
Vec3 stresslet_real_sum(const StressletPairBuffer& b, double xi);

// sum_j T^R_ijk(r_j) a_j,k over the pairs of b (separations r, normals a in its f), added
// to m (xx, yy, zz, xy, xz, yz): the self matrices' real-space part, vectorised alike.
void stresslet_real_matrix_sum(const PairBuffer& b, double xi, double m[6]);

} // namespace capsim
