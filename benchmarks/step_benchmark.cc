// Cost of one explicit step of the discrete model for different sets of
// active effects, on the same cavity (f = 25) at the same injected length
// (phi = 0.15, so contacts exist). Compare medians: an elastic frictionless
// scene must be measurably cheaper than the full one.
#include <wirefem/discrete/chain_model.h>
#include <wirefem/scene/scene_reader.h>

#include <benchmark/benchmark.h>

namespace
{
  using namespace wirefem;

  scene::Scene make(const std::vector<std::string> &extra)
  {
    std::vector<std::string> o = {"Cavity/Radius=25", "Injection/Maximum packing density=0.4"};
    o.insert(o.end(), extra.begin(), extra.end());
    return scene::read_scene("", o);
  }

  void run(benchmark::State &state, const scene::Scene &s)
  {
    discrete::ChainModel m(s);
    const double L = 0.15 * M_PI * 25.0 * 25.0;
    while (m.injected_length() < L)
      m.step();
    for (auto _ : state)
      m.step();
    state.counters["nodes"] = m.chain().n_active();
    state.counters["contacts"] = m.last_step().n_self_contacts + m.last_step().n_wall_contacts;
    state.SetItemsProcessed(state.iterations() * m.chain().n_active());
  }

  void full(benchmark::State &st)
  {
    run(st, make({"Contact/Friction/Static coefficient=5", "Wire/Plasticity/Yield curvature=0.04"}));
  }
  void elastic_frictionless(benchmark::State &st)
  {
    run(st, make({"Contact/Friction/Static coefficient=0", "Wire/Plasticity/Enabled=false"}));
  }
  void elastic_frictionless_neutral_effects_kept(benchmark::State &st)
  {
    run(st, make({"Contact/Friction/Static coefficient=0", "Wire/Plasticity/Enabled=false",
                  "Debug/Keep neutral effects=true"}));
  }
  void no_self_contact(benchmark::State &st)
  {
    run(st, make({"Contact/Friction/Static coefficient=0", "Wire/Plasticity/Enabled=false",
                  "Contact/Self contact=false"}));
  }
} // namespace

BENCHMARK(full)->Unit(benchmark::kMicrosecond);
BENCHMARK(elastic_frictionless)->Unit(benchmark::kMicrosecond);
BENCHMARK(elastic_frictionless_neutral_effects_kept)->Unit(benchmark::kMicrosecond);
BENCHMARK(no_self_contact)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
