#pragma once
// A sparse matrix made of whole 3 x 3 blocks (a mesh's node pairs), stored block row by
// block row, for the products of an iterative solver. Each node row multiplies its
// neighbours' 3-vectors by fixed-size 3 x 3 blocks; at mesh level 4 BiCGSTAB with it
// took 35-40 % of its time with Eigen's scalar column-major product of the same matrix
// (docs/method.md). It plugs into Eigen's iterative solvers as a matrix-free
// operator (Eigen's documented "matrix-free solvers" extension: EigenBase, traits and a
// generic_product_impl), so the solver itself stays Eigen's. The implicit step builds,
// shifts and scales its W in this form (dynamics/stiff_membrane.cpp): W is stored once.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <stdexcept>
#include <vector>

namespace capsim {
class BlockRows;
} // namespace capsim

namespace Eigen::internal {
template <>
struct traits<capsim::BlockRows> : public traits<Eigen::SparseMatrix<double>> {};
} // namespace Eigen::internal

namespace capsim {

class BlockRows : public Eigen::EigenBase<BlockRows> {
public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };

  BlockRows() = default;
  // The blocks of m, whose columns 3J, 3J + 1, 3J + 2 share one pattern of whole blocks
  // (three adjacent rows starting at a multiple of 3); throws std::logic_error otherwise.
  explicit BlockRows(const Eigen::SparseMatrix<double>& m);

  Eigen::Index rows() const { return 3 * Eigen::Index(start_.size() - 1); }
  Eigen::Index cols() const { return rows(); }

  // this <- I + s * this; every diagonal block must be stored.
  void scale_and_add_identity(double s);
  // Row block i <- left[i] * row block i: the product with a block-diagonal matrix.
  void multiply_rows(const std::vector<Eigen::Matrix3d>& left);
  // The diagonal blocks, row block by row block.
  std::vector<Eigen::Matrix3d> diagonal_blocks() const;
  // The same matrix in Eigen's compressed column storage (for a direct solver).
  Eigen::SparseMatrix<double> to_sparse() const;

  // y += alpha * this * x, for x and y of rows() values that do not overlap.
  void multiply_add(double alpha, const double* x, double* y) const {
    const std::less<const double*> before; // a total order, unlike < across arrays
    if (before(x, y + rows()) && before(y, x + rows()))
      throw std::logic_error("BlockRows: the product's input and output overlap");
    const int n = int(start_.size()) - 1;
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int k = start_[i]; k < start_[i + 1]; ++k)
        sum.noalias() += block_[k] * Eigen::Map<const Eigen::Vector3d>(x + 3 * col_[k]);
      Eigen::Map<Eigen::Vector3d>(y + 3 * i) += alpha * sum;
    }
  }

  template <class Rhs>
  Eigen::Product<BlockRows, Rhs, Eigen::AliasFreeProduct>
  operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<BlockRows, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

private:
  // The index in block_ of row block i's diagonal block; throws if it is not stored.
  int diagonal(int i) const;

  std::vector<int> start_{0};          // row block i's blocks: start_[i] to start_[i + 1]
  std::vector<int> col_;               // the column block of each block
  std::vector<Eigen::Matrix3d> block_; // the blocks, row block by row block
};

inline BlockRows::BlockRows(const Eigen::SparseMatrix<double>& m) {
  if (m.rows() != m.cols() || m.rows() % 3 != 0)
    throw std::logic_error("BlockRows: the matrix is not square of 3x3 blocks");
  const int n = int(m.rows()) / 3;
  const int* outer = m.outerIndexPtr();
  const int* inner = m.innerIndexPtr();
  const double* value = m.valuePtr();
  const auto* nnz = m.innerNonZeroPtr(); // null when compressed
  auto end = [&](int k) { return nnz ? outer[k] + nnz[k] : outer[k + 1]; };
  // Whether entry p of column k starts a whole block: three adjacent rows from a
  // multiple of 3.
  auto starts_block = [&](int k, int p) {
    return inner[p] % 3 == 0 && p + 2 < end(k) && inner[p + 2] == inner[p] + 2;
  };
  // Counts the blocks of each row block from the first column of each column block.
  std::vector<int> count(n + 1, 0);
  for (int j = 0; j < n; ++j) {
    const int len = end(3 * j) - outer[3 * j];
    for (int b = 1; b < 3; ++b)
      if (end(3 * j + b) - outer[3 * j + b] != len)
        throw std::logic_error("BlockRows: the matrix is not made of 3x3 blocks");
    for (int p = outer[3 * j]; p < end(3 * j); p += 3) {
      if (!starts_block(3 * j, p))
        throw std::logic_error("BlockRows: the matrix is not made of 3x3 blocks");
      ++count[inner[p] / 3 + 1];
    }
  }
  start_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i)
    start_[i + 1] = start_[i] + count[i + 1];
  col_.resize(start_[n]);
  block_.resize(start_[n]);
  std::vector<int> next(start_.begin(), start_.end() - 1);
  for (int j = 0; j < n; ++j)
    for (int p = outer[3 * j]; p < end(3 * j); p += 3) {
      const int slot = next[inner[p] / 3]++;
      col_[slot] = j;
      for (int b = 0; b < 3; ++b) {
        const int q = outer[3 * j + b] + (p - outer[3 * j]); // same row in column 3j + b
        for (int a = 0; a < 3; ++a)
          block_[slot](a, b) = value[q + a];
      }
    }
}

inline int BlockRows::diagonal(int i) const {
  for (int k = start_[i]; k < start_[i + 1]; ++k)
    if (col_[k] == i)
      return k;
  throw std::logic_error("BlockRows: a diagonal block is not stored");
}

inline void BlockRows::scale_and_add_identity(double s) {
  for (Eigen::Matrix3d& b : block_)
    b *= s;
  for (int i = 0; i + 1 < int(start_.size()); ++i)
    block_[diagonal(i)] += Eigen::Matrix3d::Identity();
}

inline void BlockRows::multiply_rows(const std::vector<Eigen::Matrix3d>& left) {
  if (left.size() + 1 != start_.size())
    throw std::logic_error("BlockRows: one left factor per row block is needed");
  for (size_t i = 0; i < left.size(); ++i)
    for (int k = start_[i]; k < start_[i + 1]; ++k)
      block_[k] = left[i] * block_[k]; // products evaluate into a temporary first
}

inline std::vector<Eigen::Matrix3d> BlockRows::diagonal_blocks() const {
  std::vector<Eigen::Matrix3d> d(start_.size() - 1);
  for (size_t i = 0; i < d.size(); ++i)
    d[i] = block_[diagonal(int(i))];
  return d;
}

inline Eigen::SparseMatrix<double> BlockRows::to_sparse() const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * block_.size());
  for (int i = 0; i + 1 < int(start_.size()); ++i)
    for (int k = start_[i]; k < start_[i + 1]; ++k)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          trip.emplace_back(3 * i + a, 3 * col_[k] + b, block_[k](a, b));
  Eigen::SparseMatrix<double> m(rows(), cols());
  m.setFromTriplets(trip.begin(), trip.end());
  return m;
}

} // namespace capsim

namespace Eigen::internal {
// dst += alpha * lhs * rhs for the solvers' products with a dense vector.
template <class Rhs>
struct generic_product_impl<capsim::BlockRows, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<capsim::BlockRows, Rhs,
                                generic_product_impl<capsim::BlockRows, Rhs>> {
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const capsim::BlockRows& lhs, const Rhs& rhs,
                            const double& alpha) {
    const Eigen::Ref<const Eigen::VectorXd> x(rhs); // copies only a lazy or strided rhs
    Eigen::Ref<Eigen::VectorXd> y(dst);
    lhs.multiply_add(alpha, x.data(), y.data());
  }
};
} // namespace Eigen::internal
