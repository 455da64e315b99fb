// The one place that knows both models: builds the one a scene asks for.
#pragma once

#include <wirefem/core/model.h>
#include <wirefem/scene/parameters.h>

#include <memory>
#include <string>

namespace wirefem::simulation
{
  /// The model the scene asks for (Model = discrete or fem).
  std::unique_ptr<core::Model> make_model(const scene::Scene &scene);
  /// The class of a model as the program sees it (summary.json's "solver":
  /// the validation report shows which class ran each case).
  std::string solver_name(const core::Model &model);
} // namespace wirefem::simulation
