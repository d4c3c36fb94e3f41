#pragma once
// Assembly of the membrane forces of one capsule and the traction jump q that enters the
// boundary integral (eq. 2.2). Sign (docs/conventions.md): q_i = (dW/dx_i) / A_i, so that
// a stretched capsule in quiescent fluid relaxes.
#include "common/choice.hpp"
#include "membrane/bending.hpp"
#include "membrane/hessian_part.hpp"
#include "membrane/surface_tension.hpp"
#include "membrane/tension_field.hpp"
#include "mesh/icosphere.hpp"

#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace capsim {

// How nodal forces become the nodal traction field q.
//  lumped:     q_i = F_i / A_i with A_i the lumped (one-third) node area. Default: it
//  costs
//              nothing, is positive and local, and keeps int q dA = sum F exactly; its
//              error is O(h^2), the same order as the flat-triangle geometry.
//  consistent: solve M q = F with the P1 mass matrix M on the current surface, so that
//  the
//              P1 field q reproduces the weak form (eq. 3.1) exactly.
enum class LoadMapping { lumped, consistent };

// The names of membrane.load, written once: the run key, its parsing and its printing.
inline constexpr Choice<LoadMapping> kLoadMappings[] = {
    {"lumped", LoadMapping::lumped}, {"consistent", LoadMapping::consistent}};

LoadMapping parse_load_mapping(const std::string& name); // throws on unknown names
std::string to_string(LoadMapping m);

// What the interface is: the paper's neo-Hookean membrane (eq. 2.11, with the optional
// bending and wrinkling), or a drop's isotropic surface tension (surface_tension.hpp),
// for emulsions and for the exact small-deformation results of drops (Taylor 1932) that
// test the viscosity ratio. A drop has no reference state and no IMEX Jacobian.
enum class MembraneLaw { neo_hookean, drop };

// The names of membrane.law, written once: the run key, its parsing and its printing.
inline constexpr Choice<MembraneLaw> kMembraneLaws[] = {
    {"neo_hookean", MembraneLaw::neo_hookean}, {"drop", MembraneLaw::drop}};

MembraneLaw parse_membrane_law(const std::string& name); // throws on unknown names
std::string to_string(MembraneLaw m);

class Membrane {
public:
  // reference: stress-free node positions (the initial sphere of radius a = 1); gs: the
  // shear modulus; kb: the bending modulus (membrane/bending.hpp; 0 = none, the paper);
  // wrinkling: the relaxed (tension-field) energy of membrane/tension_field.hpp instead
  // of eq. 2.11 (false: the paper's membrane). law drop: gs is the surface tension sigma
  // and kb, wrinkling must be 0, false (std::invalid_argument otherwise).
  Membrane(const Topology& topo, const Vec3* reference, double gs, double kb = 0,
           bool wrinkling = false, MembraneLaw law = MembraneLaw::neo_hookean);

  // Fills grad with dW/dx (size num_nodes) and returns the energy W (elastic plus
  // bending).
  double energy_gradient(const Vec3* x, std::vector<Vec3>& grad) const;
  double energy(const Vec3* x) const;

  // Traction jump q at the nodes from the energy gradient.
  void nodal_load(const Vec3* x, const std::vector<Vec3>& grad, LoadMapping mapping,
                  std::vector<Vec3>& q) const;

  // dq/dx of the lumped load q_i = (dW/dx_i) / A_i of the elastic energy at x, with
  // grad = dW/dx there: (1/A_i) d2W/dx_i dx_j - q_i (dA_i/dx_j)^T, a 3N x 3N matrix
  // (row 3 i + a, column 3 j + b) with the sparsity of the mesh's node neighbours (and
  // their hinges' opposite nodes with bending). With bending, its Gauss-Newton part
  // (exact where the hinges keep their reference angles, as under a uniform inflation).
  // With HessianPart::positive, each element's Hessian is its positive semidefinite part
  // (neo_hookean_hessian.hpp: what the implicit step needs where elements are
  // compressed). Not for a drop (std::logic_error: its runs refuse the IMEX scheme).
  Eigen::SparseMatrix<double> load_jacobian(const Vec3* x, const std::vector<Vec3>& grad,
                                            HessianPart part = HessianPart::exact) const;
  // The same as triplets (row, column, value), duplicates not yet summed, in an order
  // that depends only on the mesh: what an assembly into a fixed pattern needs
  // (common/fixed_pattern.hpp).
  std::vector<Eigen::Triplet<double>>
  load_jacobian_triplets(const Vec3* x, const std::vector<Vec3>& grad,
                         HessianPart part = HessianPart::exact) const;

  // Principal tensions and area dilatation of every element at positions x, of the
  // membrane's own energy (relaxed with wrinkling: then T2 >= 0; a drop's: T1 = T2 = 1).
  std::vector<ElementTensions> element_tensions(const Vec3* x) const;
  // The same for the paper's energy (eq. 2.10) at x, whichever energy the membrane has:
  // with wrinkling, T2 < 0 marks where it wrinkles (a drop's own: nothing is compressed).
  std::vector<ElementTensions> neo_hookean_element_tensions(const Vec3* x) const;

  const Topology& topology() const { return topo_; }
  double shear_modulus() const { return gs_; }
  double bending_modulus() const { return kb_; }
  bool wrinkling() const { return wrinkling_; }
  MembraneLaw law() const { return law_; }
  // The reference state of every element (what a device copy of the membrane needs).
  const std::vector<ElementReference>& references() const { return refs_; }
  // Every hinge and its reference (membrane/bending.hpp); empty when kb = 0.
  const std::vector<Hinge>& hinges() const { return hinges_; }
  const std::vector<HingeReference>& hinge_references() const { return hinge_refs_; }

private:
  Topology topo_;
  std::vector<ElementReference> refs_;
  double gs_;
  double kb_;
  bool wrinkling_;
  MembraneLaw law_;
  std::vector<Hinge> hinges_; // empty when kb = 0
  std::vector<HingeReference> hinge_refs_;

  std::vector<ElementTensions> drop_tensions(const Vec3* x) const;
  // Adds the bending part of load_jacobian (node areas `area`) to trip.
  void add_bending_jacobian(const Vec3* x, const std::vector<double>& area,
                            std::vector<Eigen::Triplet<double>>& trip) const;
};

} // namespace capsim
