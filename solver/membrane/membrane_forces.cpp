#include "membrane/membrane_forces.hpp"

#include "membrane/neo_hookean_hessian.hpp"
#include "mesh/surface_geometry.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <map>
#include <stdexcept>

namespace capsim {

LoadMapping parse_load_mapping(const std::string& name) {
  return parse_choice("membrane.load", name, kLoadMappings);
}

std::string to_string(LoadMapping m) {
  return choice_name(m, kLoadMappings);
}

MembraneLaw parse_membrane_law(const std::string& name) {
  return parse_choice("membrane.law", name, kMembraneLaws);
}

std::string to_string(MembraneLaw m) {
  return choice_name(m, kMembraneLaws);
}

Membrane::Membrane(const Topology& topo, const Vec3* reference, double gs, double kb,
                   bool wrinkling, MembraneLaw law)
    : topo_(topo), gs_(gs), kb_(kb), wrinkling_(wrinkling), law_(law) {
  if (law == MembraneLaw::drop && (kb != 0 || wrinkling))
    throw std::invalid_argument("Membrane: a drop has neither bending nor wrinkling");
  refs_.reserve(topo.triangles.size());
  for (const auto& t : topo.triangles)
    refs_.push_back(
        make_element_reference(reference[t[0]], reference[t[1]], reference[t[2]]));
  if (kb > 0) {
    hinges_ = make_hinges(topo);
    for (const Hinge& h : hinges_)
      hinge_refs_.push_back(make_hinge_reference(reference[h.a], reference[h.b],
                                                 reference[h.c], reference[h.d]));
  }
}

// Each hinge's Gauss-Newton Hessian kb w dtheta/dx (dtheta/dx)^T (membrane/bending.hpp),
// divided by the node areas as the elastic part. It holds the bending modes' stiffness
// (~ kb / h^4 at the element scale) and is positive semi-definite; the term left out,
// kb w (theta - theta0) d2theta/dx2, vanishes at the reference shape and grows only with
// the turn of a hinge. A W-method keeps its order with an approximate J (docs/method.md).
void Membrane::add_bending_jacobian(const Vec3* x, const std::vector<double>& area,
                                    std::vector<Eigen::Triplet<double>>& trip) const {
  for (size_t e = 0; e < hinges_.size(); ++e) {
    const Hinge& h = hinges_[e];
    const int node[4] = {h.a, h.b, h.c, h.d};
    Vec3 g[4];
    hinge_angle_gradient(x[h.a], x[h.b], x[h.c], x[h.d], g);
    const double stiffness = kb_ * hinge_refs_[e].weight;
    for (int i = 0; i < 4; ++i) {
      const double gi[3] = {g[i].x, g[i].y, g[i].z};
      for (int j = 0; j < 4; ++j) {
        const double gj[3] = {g[j].x, g[j].y, g[j].z};
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            trip.emplace_back(3 * node[i] + a, 3 * node[j] + b,
                              stiffness * gi[a] * gj[b] / area[node[i]]);
      }
    }
  }
}

Eigen::SparseMatrix<double> Membrane::load_jacobian(const Vec3* x,
                                                    const std::vector<Vec3>& grad,
                                                    HessianPart part) const {
  const std::vector<Eigen::Triplet<double>> trip = load_jacobian_triplets(x, grad, part);
  Eigen::SparseMatrix<double> jac(3 * topo_.num_nodes, 3 * topo_.num_nodes);
  jac.setFromTriplets(trip.begin(), trip.end()); // sums the duplicates
  return jac;
}

std::vector<Eigen::Triplet<double>>
Membrane::load_jacobian_triplets(const Vec3* x, const std::vector<Vec3>& grad,
                                 HessianPart part) const {
  if (law_ == MembraneLaw::drop)
    throw std::logic_error("Membrane: a drop has no load Jacobian");
  const std::vector<double> area = node_areas(topo_, x);
  // Each element fills its own 81 slots, so the elements run in parallel (a single
  // capsule's implicit step has no capsules to share among the threads).
  std::vector<Eigen::Triplet<double>> trip(81 * refs_.size());
  trip.reserve(trip.size() + 144 * hinges_.size());
#pragma omp parallel for schedule(static)
  for (size_t e = 0; e < refs_.size(); ++e) {
    const auto& t = topo_.triangles[e];
    const Matrix9 h = membrane_element_hessian(refs_[e], gs_, wrinkling_, x[t[0]],
                                               x[t[1]], x[t[2]], part);
    // d(area_e)/dx_k = n_hat x (x_{k+2} - x_{k+1}) / 2; node i holds a third of it.
    const Vec3 an = area_vector2(x[t[0]], x[t[1]], x[t[2]]);
    const Vec3 n_hat = (1.0 / norm(an)) * an;
    Vec3 darea[3];
    for (int k = 0; k < 3; ++k)
      darea[k] = (1.0 / 6.0) * cross(n_hat, x[t[(k + 2) % 3]] - x[t[(k + 1) % 3]]);
    Eigen::Triplet<double>* slot = &trip[81 * e];
    for (int i = 0; i < 3; ++i) {
      const int ni = t[i];
      const Vec3 qi = (1.0 / (area[ni] * area[ni])) * grad[ni];
      const double qa[3] = {qi.x, qi.y, qi.z};
      for (int j = 0; j < 3; ++j) {
        const double da[3] = {darea[j].x, darea[j].y, darea[j].z};
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            *slot++ = {3 * ni + a, 3 * t[j] + b,
                       h(3 * i + a, 3 * j + b) / area[ni] - qa[a] * da[b]};
      }
    }
  }
  add_bending_jacobian(x, area, trip);
  return trip;
}

std::vector<ElementTensions> Membrane::element_tensions(const Vec3* x) const {
  if (law_ == MembraneLaw::drop)
    return drop_tensions(x);
  std::vector<ElementTensions> out(refs_.size());
  for (size_t e = 0; e < refs_.size(); ++e) {
    const auto& t = topo_.triangles[e];
    out[e] = membrane_tensions(refs_[e], wrinkling_, x[t[0]], x[t[1]], x[t[2]]);
  }
  return out;
}

std::vector<ElementTensions> Membrane::neo_hookean_element_tensions(const Vec3* x) const {
  if (law_ == MembraneLaw::drop)
    return drop_tensions(x);
  std::vector<ElementTensions> out(refs_.size());
  for (size_t e = 0; e < refs_.size(); ++e) {
    const auto& t = topo_.triangles[e];
    out[e] = neo_hookean_tensions(refs_[e], x[t[0]], x[t[1]], x[t[2]]);
  }
  return out;
}

// The isotropic tension sigma = gs, over gs, and each element's area over its reference.
std::vector<ElementTensions> Membrane::drop_tensions(const Vec3* x) const {
  std::vector<ElementTensions> out(refs_.size());
  for (size_t e = 0; e < refs_.size(); ++e) {
    const auto& t = topo_.triangles[e];
    out[e] = {1.0, 1.0,
              0.5 * norm(area_vector2(x[t[0]], x[t[1]], x[t[2]])) / refs_[e].area0};
  }
  return out;
}

double Membrane::energy_gradient(const Vec3* x, std::vector<Vec3>& grad) const {
  grad.assign(topo_.num_nodes, Vec3{});
  double w = 0;
  for (size_t e = 0; e < refs_.size(); ++e) {
    const auto& t = topo_.triangles[e];
    Vec3 g[3];
    w += law_ == MembraneLaw::drop
             ? surface_tension_element(gs_, x[t[0]], x[t[1]], x[t[2]], g)
             : membrane_element(refs_[e], gs_, wrinkling_, x[t[0]], x[t[1]], x[t[2]], g);
    for (int k = 0; k < 3; ++k)
      grad[t[k]] += g[k];
  }
  for (size_t e = 0; e < hinges_.size(); ++e) {
    const Hinge& h = hinges_[e];
    Vec3 g[4];
    w += bending_hinge(hinge_refs_[e], kb_, x[h.a], x[h.b], x[h.c], x[h.d], g);
    grad[h.a] += g[0];
    grad[h.b] += g[1];
    grad[h.c] += g[2];
    grad[h.d] += g[3];
  }
  return w;
}

double Membrane::energy(const Vec3* x) const {
  std::vector<Vec3> g;
  return energy_gradient(x, g);
}

namespace {

// P1 mass matrix: int phi_a phi_b dA = A/12 (1 + delta_ab) on each triangle.
Eigen::SparseMatrix<double> mass_matrix(const Topology& topo, const Vec3* x) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * topo.triangles.size());
  for (const auto& t : topo.triangles) {
    double a = 0.5 * norm(area_vector2(x[t[0]], x[t[1]], x[t[2]]));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        trip.emplace_back(t[i], t[j], a / 12.0 * (i == j ? 2 : 1));
  }
  Eigen::SparseMatrix<double> m(topo.num_nodes, topo.num_nodes);
  m.setFromTriplets(trip.begin(), trip.end());
  return m;
}

} // namespace

std::vector<Hinge> make_hinges(const Topology& topo) {
  // The triangle on each side of an edge: (a, b, c) has the directed edge a -> b, its
  // neighbour across it has b -> a.
  std::map<std::pair<int, int>, int> opposite; // directed edge -> third node
  for (const auto& t : topo.triangles)
    for (int k = 0; k < 3; ++k)
      opposite[{t[k], t[(k + 1) % 3]}] = t[(k + 2) % 3];
  std::vector<Hinge> hinges;
  for (const auto& [edge, c] : opposite) {
    auto [a, b] = edge;
    if (a > b)
      continue; // each edge once
    auto other = opposite.find({b, a});
    if (other == opposite.end())
      throw std::invalid_argument("make_hinges: the mesh is not closed");
    hinges.push_back({a, b, c, other->second});
  }
  return hinges;
}

void Membrane::nodal_load(const Vec3* x, const std::vector<Vec3>& grad,
                          LoadMapping mapping, std::vector<Vec3>& q) const {
  const int n = topo_.num_nodes;
  q.resize(n);
  if (mapping == LoadMapping::lumped) {
    std::vector<double> area = node_areas(topo_, x);
    for (int i = 0; i < n; ++i)
      q[i] = (1.0 / area[i]) * grad[i];
    return;
  }
  // The mass matrix is SPD with condition number ~4 on a regular mesh: CG converges in a
  // handful of iterations to near machine precision.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-13);
  const Eigen::SparseMatrix<double> mass = mass_matrix(topo_, x); // cg keeps a reference
  cg.compute(mass);
  Eigen::VectorXd rhs(n), sol;
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < n; ++i)
      rhs[i] = (&grad[i].x)[a];
    sol = cg.solve(rhs);
    for (int i = 0; i < n; ++i)
      (&q[i].x)[a] = sol[i];
  }
}

} // namespace capsim
