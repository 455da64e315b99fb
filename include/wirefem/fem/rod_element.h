// The planar geometrically exact (Simo-Reissner) rod element, independent of
// the mesh: given the nodal values (x, y, theta) of one element and its shape
// functions at the quadrature points, it returns the internal force vector
// (the residual), its consistent tangent, the stored energies and the updated
// quadrature-point history.
//
// Kinematics (material arc length S, section angle theta):
//   Gamma = R(theta)^T r' - e1 = (eps, gamma)   axial and shear strain
//   kappa = theta'                               curvature
//   N = EA eps + eta_a d(eps)/dt,  Q = GA gamma,  M = M_law(kappa) + eta_b d(kappa)/dt
// The moment comes from the elastoplastic moment-curvature law shared with the
// discrete model; its algorithmic tangent enters the element tangent. The
// rates are backward differences over the step (viscous dashpots, optional).
//
// Locking: the stiffness is integrated with p Gauss points for degree p
// (uniform reduced integration), which keeps the element free of shear and
// membrane locking at slenderness 1e4 (tests/fem_test.cc).
//
// Kirchhoff (shear-rigid) variant: the shear strain is constrained to zero by
// a penalty GA_K = shear_penalty * EA, still under reduced integration so the
// constraint does not lock; the shear energy it stores is reported
// separately and vanishes as the penalty grows.
//
// Local dof order: 3 a + c for node a (0 = left vertex, 1 = right vertex,
// then interior nodes from left to right) and component c (0 x, 1 y, 2 theta).
#pragma once

#include <wirefem/material/moment_curvature_law.h>

#include <vector>

namespace wirefem::fem
{
  /// Shape functions of one element at its quadrature points.
  struct ElementShape
  {
    static constexpr unsigned int max_degree = 3; ///< at most 12 dofs
    static constexpr unsigned int max_points = 8; ///< Gauss points
    unsigned int n_nodes = 0;
    unsigned int n_q = 0;
    double length = 0.0;
    std::vector<double> weight;        ///< quadrature weight times length
    std::vector<double> N;             ///< N[q * n_nodes + a]
    std::vector<double> dN;            ///< dN/dS, same layout
    std::vector<double> node_position; ///< rest position of node a in [0, 1] along the element

    double value(unsigned int q, unsigned int a) const { return N[q * n_nodes + a]; }
    double derivative(unsigned int q, unsigned int a) const { return dN[q * n_nodes + a]; }

    /// Lagrange element of degree p (deal.II FE_Q node layout) on an element
    /// of rest length h, with n_q Gauss points (degree <= max_degree,
    /// n_q <= max_points).
    static ElementShape lagrange(unsigned int degree, double h, unsigned int n_q);
  };

  /// Values N and derivatives dN/dxi at xi in [0, 1] of the Lagrange
  /// polynomials with nodes at node_position.
  void lagrange_basis(const std::vector<double> &node_position, double xi, double *N, double *dN);

  struct SectionProperties
  {
    double EA = 1000.0;
    double GA = 400.0;
    double axial_viscosity = 0.0;   ///< eta_a: N_visc = eta_a d(eps)/dt
    double bending_viscosity = 0.0; ///< eta_b: M_visc = eta_b d(kappa)/dt
  };

  /// History and last strains of one quadrature point.
  struct PointState
  {
    material::PlasticState plastic;
    double axial_strain = 0.0;
    double shear_strain = 0.0;
    double curvature = 0.0;
  };

  struct ElementResult
  {
    std::vector<double> residual;         ///< internal force (elastic + viscous), 3 n_nodes
    std::vector<double> viscous_residual; ///< the viscous part of residual
    /// d (residual + (viscous_scale - 1) viscous_residual) / d dofs, row major; empty if not asked for
    std::vector<double> tangent;
    double axial_energy = 0.0;
    double shear_energy = 0.0;
    double bending_energy = 0.0;   ///< elastic part 1/2 EI (kappa - kappa_p)^2
    double plastic_work = 0.0;     ///< this increment
    std::vector<PointState> state; ///< updated history
  };

  /// Evaluates one element. dofs: 3 n_nodes values; old: n_q committed states;
  /// dt > 0 enables the viscous dashpots (dt <= 0: none). viscous_scale
  /// weights the viscous part in the tangent only (a time integrator that
  /// blends elastic forces but not dissipative ones needs them weighted
  /// differently).
  void evaluate_rod_element(const ElementShape &shape, const SectionProperties &section,
                            const material::MomentCurvatureLaw &law, const double *dofs,
                            const PointState *old, double dt, bool want_tangent, ElementResult &out,
                            double viscous_scale = 1.0);

  /// The tangent of evaluate_rod_element by automatic differentiation of
  /// the residual (Sacado): the oracle of the hand-derived tangent in tests.
  std::vector<double> rod_element_tangent_by_ad(const ElementShape &shape, const SectionProperties &section,
                                                const material::MomentCurvatureLaw &law, const double *dofs,
                                                const PointState *old, double dt, double viscous_scale = 1.0);

  /// Stored elastic energy of the element for the given dofs and fixed
  /// plastic strains (no return mapping): the potential of the residual in
  /// the elastic range (finite-difference tests).
  double rod_element_energy(const ElementShape &shape, const SectionProperties &section,
                            const material::MomentCurvatureLaw &law, const double *dofs,
                            const PointState *old);
} // namespace wirefem::fem
