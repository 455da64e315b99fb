#include <wirefem/discrete/chain_model.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/simulation/make_model.h>

namespace wirefem::simulation
{
  std::unique_ptr<core::Model> make_model(const scene::Scene &scene)
  {
    if (scene.model == scene::ModelType::fem)
      return std::make_unique<fem::RodModel>(scene);
    return std::make_unique<discrete::ChainModel>(scene);
  }
} // namespace wirefem::simulation
