// The one place that knows both models: builds the one a scene asks for.
#pragma once

#include <wirefem/core/model.h>
#include <wirefem/scene/parameters.h>

#include <memory>

namespace wirefem::simulation
{
  /// The model the scene asks for (Model = discrete or fem).
  std::unique_ptr<core::Model> make_model(const scene::Scene &scene);
} // namespace wirefem::simulation
