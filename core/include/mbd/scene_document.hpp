// Reading the scene as written (Model::document, every `base:` merged in) for keys the Model does
// not hold: an element's documented keys (its stiction velocity, a wheel's radius).
#pragma once

#include <mbd/model.hpp>

#include <string>

namespace mbd {

// The map of the element named `name` in the document's list `section` ("joints", "forces"), or
// null (no document, no such list or element, e.g. the core's gravity element).
const Param* scene_element_node(const Model& model, const std::string& section, const std::string& name);

}  // namespace mbd
