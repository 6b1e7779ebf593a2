// The inputs a scene reads (run_setup.hpp): its {type: input, name: NAME} time functions.
#include "simulation/run_setup.hpp"

#include <algorithm>

namespace mbd {

namespace {

void collect_inputs(const Param& node, std::vector<SceneInput>& found) {
    if (node.is_map()) {
        auto type = node.fields.find("type"), name = node.fields.find("name");
        if (type != node.fields.end() && type->second.is_scalar() && type->second.text == "input" &&
            name != node.fields.end() && name->second.is_scalar())
            found.push_back({name->second.text, node.location()});
        for (const auto& field : node.fields) collect_inputs(field.second, found);
    } else if (node.is_list()) {
        for (const Param& item : node.items) collect_inputs(item, found);
    }
}

}  // namespace

std::vector<SceneInput> scene_inputs(const Model& model) {
    std::vector<SceneInput> found;
    if (model.document) collect_inputs(*model.document, found);
    return found;
}

void refuse_scene_inputs(const Model& model) {
    const std::vector<SceneInput> inputs = scene_inputs(model);
    if (inputs.empty()) return;
    throw InputError(inputs.front().where, "the input '" + inputs.front().name +
                                               "' has a value only while a Simulator steps the scene (set_input, "
                                               "docs/embedding.md); a whole run has no inputs: give it a time "
                                               "function instead");
}

}  // namespace mbd
