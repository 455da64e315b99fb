// The one place that knows both models: builds the one a scene asks for.
#pragma once

#include <wirefem/core/model.h>
#include <wirefem/scene/parameters.h>

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>

namespace wirefem::simulation
{
  /// The model the scene asks for (Model = discrete or fem).
  std::unique_ptr<core::Model> make_model(const scene::Scene &scene);
  /// The class of a model as the program sees it (summary.json's "solver":
  /// the validation report shows which class ran each case).
  std::string solver_name(const core::Model &model);
  /// What every summary.json says of the run that wrote it: the set-up, the
  /// model, its class (solver_name), the effects it built and the version.
  void describe_run(nlohmann::json &j, const core::Model &model, const std::string &setup);
} // namespace wirefem::simulation
