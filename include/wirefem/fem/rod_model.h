// The geometrically exact rod FEM (docs/model.md) behind the same Model
// interface as the discrete chain: Simo-Reissner (or penalty-Kirchhoff)
// elements of degree 1-3 on a deal.II Triangulation<1,2>, the elastoplastic
// moment-curvature law at the quadrature points, penalty contact with
// regularised Coulomb friction, implicit generalized-alpha time stepping with
// Newton, line search and an adaptive step, a deal.II sparse matrix and
// KLU (fem::SparseDirect).
//
// The loading is the injection or, with Set-up = cantilever, the clamp: the
// rod held at one end and loaded at the other, followed statically along its
// load history.
//
// Injection as a moving boundary: the mesh holds the whole wire that can ever
// enter, at rest length, with material coordinate S. At time t the material
// in the channels (S outside (s_L(t), s_R(t))) is prescribed - straight on
// the channel axis, theta along it, moving at the injection speed - so that
// the position and tangent are clamped at the inlets while material flows
// in. The unknowns are the nodes between the inlets. The inlet force is the
// work of the channel reactions per injected length, over one node spacing,
// which cancels the periodic step of a node passing the inlet.
//
// deal.II stays in the .cc file.
#pragma once

#include <wirefem/core/model.h>
#include <wirefem/scene/parameters.h>

#include <memory>
#include <vector>

namespace wirefem::fem
{
  class RodModel final : public core::Model
  {
  public:
    explicit RodModel(const scene::RodScene &scene);
    ~RodModel() override;

    std::string name() const override { return "fem"; }
    std::string description() const override;
    void step() override;
    double time() const override;
    double time_step() const override;
    unsigned long n_steps() const override;
    double injected_length() const override;
    double force_left() const override;
    double force_right() const override;
    const core::EnergyLedger &energies() const override;
    core::StepReport report() const override;
    const std::vector<std::string> &active_effects() const override;
    bool finite() const override;
    core::WireState wire_state() const override;
    /// Set-up = cantilever: load increments from the current load factor,
    /// each a quasi-static Newton step; halved where Newton fails, where a
    /// section turns by more than 0.25 rad or where the path would jump from
    /// a stable to an unstable branch.
    core::Equilibrium equilibrate(double load_factor) override;
    core::CapstanState capstan_state() const override;
    std::vector<std::pair<std::string, double>> statistics() const override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;
    void print_timing(std::ostream &out) const override;

    /// Residual norms (max norm over the free dofs) of the Newton iterations
    /// of the last accepted step, the first at the predictor.
    const std::vector<double> &newton_history() const;
    /// Newton failures (step cuts) so far.
    unsigned long n_step_cuts() const;
    unsigned int n_dofs() const;

  private:
    friend struct RodModelProbe; // the tests' access to the assembly (tests/rod_probe.h)
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace wirefem::fem
