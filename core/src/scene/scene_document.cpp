// Reading the scene as written (scene_document.hpp).
#include <mbd/scene_document.hpp>

namespace mbd {

const Param* scene_element_node(const Model& model, const std::string& section, const std::string& name) {
    if (!model.document || !model.document->is_map()) return nullptr;
    const auto list = model.document->fields.find(section);
    if (list == model.document->fields.end() || !list->second.is_list()) return nullptr;
    for (const Param& item : list->second.items) {
        if (!item.is_map()) continue;
        const auto key = item.fields.find("name");
        if (key != item.fields.end() && key->second.is_scalar() && key->second.text == name) return &item;
    }
    return nullptr;
}

}  // namespace mbd
