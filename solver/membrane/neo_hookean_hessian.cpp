#include "membrane/neo_hookean_hessian.hpp"

#include <Eigen/Eigenvalues>

namespace capsim {

Matrix6 positive_part(const Matrix6& h) {
  const Eigen::SelfAdjointEigenSolver<Matrix6> eig(h);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

} // namespace capsim
