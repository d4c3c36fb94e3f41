#pragma once
// Assembly of a sparse matrix whose sparsity never changes (a mesh's node neighbours)
// from triplets. Eigen's setFromTriplets sorts and merges the triplets every time; at
// mesh level 4 that was two thirds of building a capsule's membrane Jacobian. Here it is
// done once: each later assembly adds every triplet's value into its slot, in the
// triplets' order, so the sums equal setFromTriplets' to the last bit.
#include <Eigen/SparseCore>
#include <algorithm>
#include <stdexcept>
#include <vector>

namespace capsim {

class FixedPatternAssembly {
public:
  using Matrix = Eigen::SparseMatrix<double>;
  using Triplet = Eigen::Triplet<double>;

  // Learns the pattern from trip: its rows and columns, in that order.
  FixedPatternAssembly(int rows, int cols, const std::vector<Triplet>& trip)
      : pattern_(rows, cols), slot_(trip.size()) {
    pattern_.setFromTriplets(trip.begin(), trip.end());
    pattern_.makeCompressed();
    for (size_t k = 0; k < trip.size(); ++k) {
      const int begin = pattern_.outerIndexPtr()[trip[k].col()];
      const int end = pattern_.outerIndexPtr()[trip[k].col() + 1];
      const int* inner = pattern_.innerIndexPtr();
      slot_[k] = int(std::lower_bound(inner + begin, inner + end, trip[k].row()) - inner);
    }
  }

  // The matrix of trip, which must list the same rows and columns in the same order as
  // the triplets the pattern was learnt from.
  Matrix assemble(const std::vector<Triplet>& trip) const {
    if (trip.size() != slot_.size())
      throw std::logic_error("FixedPatternAssembly: the triplets changed their pattern");
    Matrix m = pattern_;
    double* value = m.valuePtr();
    std::fill(value, value + m.nonZeros(), 0.0);
    for (size_t k = 0; k < trip.size(); ++k) {
      if (m.innerIndexPtr()[slot_[k]] != trip[k].row())
        throw std::logic_error(
            "FixedPatternAssembly: the triplets changed their pattern");
      value[slot_[k]] += trip[k].value();
    }
    return m;
  }

private:
  Matrix pattern_;
  std::vector<int> slot_; // where triplet k's value goes in pattern_.valuePtr()
};

} // namespace capsim
