#pragma once
// Separations r = x - y and loads f of the pairs of one target, structure of arrays: the
// input of the vectorised pair sums (stokeslet_sum here, screened_sum in
// real_space_sum.hpp), in double or (the real-space sum's single precision) float.
#include "common/vec3.hpp"

#include <cstddef>
#include <vector>

namespace capsim {

template <class T> struct BasicPairBuffer {
  std::vector<T> rx, ry, rz, fx, fy, fz;
  size_t n = 0;

  // Room for at least m pairs (the contents up to n are kept).
  void reserve(size_t m) {
    if (m > rx.size())
      for (auto* v : {&rx, &ry, &rz, &fx, &fy, &fz})
        v->resize(m);
  }
  // Room for at least m pairs, doubling (PeriodicCells::gather_within).
  void make_room(size_t m) {
    if (m > rx.size())
      reserve(2 * m);
  }
  void push(Vec3 r, Vec3 f) {
    if (__builtin_expect(n == rx.size(), 0))
      grow();
    rx[n] = r.x, ry[n] = r.y, rz[n] = r.z;
    fx[n] = f.x, fy[n] = f.y, fz[n] = f.z;
    ++n;
  }

private:
  __attribute__((noinline)) void grow() { reserve(2 * n + 64); }
};

using PairBuffer = BasicPairBuffer<double>;

// sum_j J(r_j) f_j over the pairs (free-space Stokeslet, stokeslet.hpp), one vectorised
// loop (AVX-512/AVX2 clones).
Vec3 stokeslet_sum(const PairBuffer& b);

} // namespace capsim
