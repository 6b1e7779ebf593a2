// scene_loader.hpp.
#include <mbd/app/scene_loader.hpp>

#include <mbd/scene.hpp>

namespace mbd {

Scene load_with(const SceneLoader& load, const std::filesystem::path& file, Registry& registry) {
    return load ? load(file, registry) : read_scene(file, registry);
}

Scene scene_of(Model model) {
    Scene scene;
    scene.document = model.document;
    scene.model = std::move(model);
    return scene;
}

}  // namespace mbd
