#include "stokes/double_layer/second_kind_solve.hpp"

#include "mesh/surface_geometry.hpp"

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <omp.h>
#include <stdexcept>
#include <unsupported/Eigen/IterativeSolvers>

namespace capsim::detail {
class SecondKindMatrix;
} // namespace capsim::detail

namespace Eigen::internal {
template <>
struct traits<capsim::detail::SecondKindMatrix>
    : public traits<Eigen::SparseMatrix<double>> {};
} // namespace Eigen::internal

namespace capsim {
namespace detail {

// The operator as Eigen's GMRES sees it: a matrix-free operator per Eigen's documented
// "matrix-free solvers" example (EigenBase, traits and a generic_product_impl), as
// common/block_rows.hpp does for BiCGSTAB, so that the solver itself stays Eigen's.
class SecondKindMatrix : public Eigen::EigenBase<SecondKindMatrix> {
public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };
  explicit SecondKindMatrix(const SecondKindOperator& op) : op_(&op) {}
  Eigen::Index rows() const { return op_->size(); }
  Eigen::Index cols() const { return op_->size(); }
  template <class Rhs>
  Eigen::Product<SecondKindMatrix, Rhs, Eigen::AliasFreeProduct>
  operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<SecondKindMatrix, Rhs, Eigen::AliasFreeProduct>(*this,
                                                                          x.derived());
  }
  const SecondKindOperator& op() const { return *op_; }

private:
  const SecondKindOperator* op_;
};

} // namespace detail
} // namespace capsim

namespace Eigen::internal {
template <class Rhs>
struct generic_product_impl<capsim::detail::SecondKindMatrix, Rhs, SparseShape,
                            DenseShape, GemvProduct>
    : generic_product_impl_base<
          capsim::detail::SecondKindMatrix, Rhs,
          generic_product_impl<capsim::detail::SecondKindMatrix, Rhs>> {
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const capsim::detail::SecondKindMatrix& lhs,
                            const Rhs& rhs, const double& alpha) {
    const Eigen::VectorXd x = rhs;
    // GMRES forms rhs - A x with x = 0 when it starts from a zero correction: A is
    // linear, so skip the (costly) double layer.
    if (x.isZero(0))
      return;
    Eigen::VectorXd y;
    lhs.op().apply(x, y);
    dst += alpha * y;
  }
};
} // namespace Eigen::internal

namespace capsim {

namespace {
Eigen::Map<const Eigen::VectorXd> as_vector(const std::vector<Vec3>& v) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three doubles");
  return Eigen::Map<const Eigen::VectorXd>(&v[0].x, 3 * Eigen::Index(v.size()));
}
std::vector<Vec3> as_vec3(const Eigen::VectorXd& v) {
  std::vector<Vec3> out(v.size() / 3);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
  return out;
}
// Rigid-body mode m (0-2 translations, 3-5 rotations about c) at position p.
Vec3 rigid_mode(int m, Vec3 p, Vec3 c) {
  const Vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return m < 3 ? e[m] : cross(e[m - 3], p - c);
}
} // namespace

SecondKindOperator::SecondKindOperator(DoubleLayerApply k, const Topology& topo,
                                       int num_capsules, const std::vector<Vec3>& x,
                                       double lambda, bool deflate, double box_volume)
    : k_(std::move(k)), num_nodes_(int(x.size())), nodes_per_capsule_(topo.num_nodes),
      num_capsules_(num_capsules), lambda_(lambda), kappa_(second_kind_kappa(lambda)),
      deflate_(deflate), periodic_(box_volume > 0), positions_(x) {
  area_.resize(num_nodes_);
  nu_.resize(num_nodes_);
  centre_.resize(num_capsules);
  volume_.resize(num_capsules);
  gram_inverse_.resize(num_capsules);
  normal_norm2_.assign(num_capsules, 0.0);
  for (int c = 0; c < num_capsules; ++c) {
    const int o = c * nodes_per_capsule_;
    const std::vector<double> a = node_areas(topo, &x[o]);
    const std::vector<Vec3> av = node_area_vectors(topo, &x[o]);
    for (int i = 0; i < nodes_per_capsule_; ++i) {
      area_[o + i] = a[i];
      nu_[o + i] = (1.0 / 6.0) * av[i];
      normal_norm2_[c] += dot(nu_[o + i], nu_[o + i]) / a[i];
    }
    centre_[c] = volume_centroid(topo, &x[o]);
    volume_[c] = enclosed_volume(topo, &x[o]);
    Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < nodes_per_capsule_; ++i)
      for (int m = 0; m < 6; ++m)
        for (int n = 0; n < 6; ++n)
          gram(m, n) += a[i] * dot(rigid_mode(m, x[o + i], centre_[c]),
                                   rigid_mode(n, x[o + i], centre_[c]));
    gram_inverse_[c] = gram.inverse();
  }
}

SecondKindOperator::SecondKindOperator(const DoubleLayer& k, const Topology& topo,
                                       int num_capsules, const std::vector<Vec3>& x,
                                       double lambda, bool deflate)
    : SecondKindOperator(
          [&k](const std::vector<Vec3>& u, std::vector<Vec3>& out) { k.apply(u, out); },
          topo, num_capsules, x, lambda, deflate) {}

void SecondKindOperator::rigid_projection(const Eigen::VectorXd& w,
                                          Eigen::VectorXd& y) const {
  y.setZero(size());
  // Each capsule's coefficients: translation (0-2) and rotation about its volume
  // centroid (3-5).
  std::vector<Eigen::Matrix<double, 6, 1>> coef(num_capsules_);
  for (int c = 0; c < num_capsules_; ++c) {
    const int o = c * nodes_per_capsule_;
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i = o; i < o + nodes_per_capsule_; ++i) {
      const Vec3 wi{w[3 * i], w[3 * i + 1], w[3 * i + 2]};
      for (int m = 0; m < 6; ++m)
        b[m] += area_[i] * dot(rigid_mode(m, positions_[i], centre_[c]), wi);
    }
    coef[c] = gram_inverse_[c] * b;
  }
  if (periodic_) { // less the volume-weighted mean translation (see the header)
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double total = 0;
    for (int c = 0; c < num_capsules_; ++c) {
      mean += volume_[c] * coef[c].head<3>();
      total += volume_[c];
    }
    for (int c = 0; c < num_capsules_; ++c)
      coef[c].head<3>() -= mean / total;
  }
  for (int c = 0; c < num_capsules_; ++c) {
    const int o = c * nodes_per_capsule_;
    for (int i = o; i < o + nodes_per_capsule_; ++i) {
      Vec3 v;
      for (int m = 0; m < 6; ++m)
        v += coef[c][m] * rigid_mode(m, positions_[i], centre_[c]);
      y[3 * i] = v.x, y[3 * i + 1] = v.y, y[3 * i + 2] = v.z;
    }
  }
}

void SecondKindOperator::normal_projection(const Eigen::VectorXd& w,
                                           Eigen::VectorXd& y) const {
  y.setZero(size());
  for (int c = 0; c < num_capsules_; ++c) {
    const int o = c * nodes_per_capsule_;
    double flux = 0; // (m, w) = sum nu_i . w_i, the rate of change of the P1 volume
    for (int i = o; i < o + nodes_per_capsule_; ++i)
      flux += dot(nu_[i], Vec3{w[3 * i], w[3 * i + 1], w[3 * i + 2]});
    const double s = flux / normal_norm2_[c];
    for (int i = o; i < o + nodes_per_capsule_; ++i) {
      const Vec3 m = (1.0 / area_[i]) * nu_[i];
      y[3 * i] = s * m.x, y[3 * i + 1] = s * m.y, y[3 * i + 2] = s * m.z;
    }
  }
}

void SecondKindOperator::apply_kernel(const Eigen::VectorXd& w,
                                      Eigen::VectorXd& y) const {
  std::vector<Vec3> kw;
  k_(as_vec3(w), kw);
  y = as_vector(kw);
  if (deflate_) {
    Eigen::VectorXd p, n;
    rigid_projection(w, p);
    normal_projection(w, n);
    y += 0.5 * (n - p);
  }
}

void SecondKindOperator::apply(const Eigen::VectorXd& w, Eigen::VectorXd& y) const {
  apply_kernel(w, y);
  y = w - kappa_ * y;
}

Eigen::VectorXd SecondKindOperator::velocity_of(const Eigen::VectorXd& w) const {
  if (!deflate_)
    return w;
  Eigen::VectorXd p;
  rigid_projection(w, p);
  return w + 0.5 * (lambda_ - 1.0) * p;
}

Eigen::VectorXd SecondKindOperator::unknown_of(const Eigen::VectorXd& u) const {
  if (!deflate_)
    return u;
  Eigen::VectorXd p;
  rigid_projection(u, p);
  return u - ((lambda_ - 1.0) / (lambda_ + 1.0)) * p;
}

SecondKindResult solve_second_kind(const Topology& topo, int num_capsules,
                                   const std::vector<Vec3>& x, double lambda,
                                   const std::vector<Vec3>& f,
                                   const QuadratureOptions& quadrature,
                                   const SecondKindOptions& options, std::vector<Vec3>& u,
                                   const SecondKindBox* box) {
  if (!(lambda > 0) || !std::isfinite(lambda))
    throw std::invalid_argument("solve_second_kind: the viscosity ratio must be positive "
                                "and finite");
  if (f.size() != x.size())
    throw std::invalid_argument("solve_second_kind: one right-hand side vector per node");
  SecondKindResult result;
  if (lambda == 1.0) { // kappa = 0: the equation is u = f
    u = f;
    return result;
  }
  const Eigen::Map<const Eigen::VectorXd> rhs = as_vector(f);
  const double f_norm = rhs.norm();
  if (f_norm == 0) { // the operator is invertible for lambda > 0: u = 0
    u.assign(f.size(), Vec3{});
    return result;
  }
  if (u.size() != f.size())
    u.assign(f.size(), Vec3{});
  std::unique_ptr<DoubleLayer> free;
  std::unique_ptr<PeriodicDoubleLayer> periodic;
  DoubleLayerApply k;
  const double t0 = omp_get_wtime();
  if (box) {
    periodic = std::make_unique<PeriodicDoubleLayer>(
        topo, num_capsules, x, box->lattice, box->ewald, quadrature, box->spectral,
        box->self_ewald, box->self_grid);
    k = [&periodic](const std::vector<Vec3>& w, std::vector<Vec3>& out) {
      periodic->apply(w, out);
    };
  } else {
    free = std::make_unique<DoubleLayer>(topo, num_capsules, x, quadrature);
    k = [&free](const std::vector<Vec3>& w, std::vector<Vec3>& out) {
      free->apply(w, out);
    };
  }
  result.setup_seconds = omp_get_wtime() - t0;
  k = [apply = std::move(k), &result](const std::vector<Vec3>& w,
                                      std::vector<Vec3>& out) {
    const double t = omp_get_wtime();
    apply(w, out);
    result.apply_seconds += omp_get_wtime() - t;
  };
  const double box_volume = box ? std::pow(box->lattice.L, 3) : 0.0;
  const SecondKindOperator op(std::move(k), topo, num_capsules, x, lambda,
                              options.deflate, box_volume);
  Eigen::VectorXd w = op.unknown_of(as_vector(u));
  // Eigen's GMRES measures its tolerance against the initial residual; we want it
  // against ||f|| (a good first guess must not tighten the stop), so GMRES solves for
  // the correction to the guess, with the tolerance rescaled.
  Eigen::VectorXd aw;
  op.apply(w, aw);
  const Eigen::VectorXd r0 = rhs - aw;
  const double r0_norm = r0.norm();
  result.residual = r0_norm / f_norm;
  if (result.residual > options.tolerance) {
    const detail::SecondKindMatrix matrix(op);
    Eigen::GMRES<detail::SecondKindMatrix, Eigen::IdentityPreconditioner> gmres;
    gmres.compute(matrix);
    gmres.setTolerance(options.tolerance * f_norm / r0_norm);
    gmres.setMaxIterations(options.max_iterations);
    gmres.set_restart(options.restart);
    const Eigen::VectorXd dw = gmres.solve(r0);
    w += dw;
    result.iterations = int(gmres.iterations());
    result.residual = gmres.error() * r0_norm / f_norm;
  }
  result.converged = result.residual <= options.tolerance;
  u = as_vec3(op.velocity_of(w));
  return result;
}

} // namespace capsim
