#include <wirefem/discrete/chain_model.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/simulation/make_model.h>
#include <wirefem/version.h>

#include <nlohmann/json.hpp>

#include <cxxabi.h>
#include <cstdlib>
#include <memory>
#include <typeinfo>

namespace wirefem::simulation
{
  std::unique_ptr<core::Model> make_model(const scene::Scene &scene)
  {
    if (scene.model == scene::ModelType::fem)
      return std::make_unique<fem::RodModel>(scene);
    return std::make_unique<discrete::ChainModel>(scene);
  }

  std::string solver_name(const core::Model &model)
  {
    const char *mangled = typeid(model).name();
    int status = 0;
    const std::unique_ptr<char, void (*)(void *)> name(
        abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
    return status == 0 && name ? name.get() : mangled;
  }

  void describe_run(nlohmann::json &j, const core::Model &model, const std::string &setup)
  {
    j["setup"] = setup;
    j["model"] = model.name();
    j["solver"] = solver_name(model);
    j["active_effects"] = model.active_effects();
    j["version"] = version();
  }
} // namespace wirefem::simulation
