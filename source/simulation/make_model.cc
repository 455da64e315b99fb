#include <wirefem/discrete/chain_model.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/simulation/make_model.h>

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
} // namespace wirefem::simulation
