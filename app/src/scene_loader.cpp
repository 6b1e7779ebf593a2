// scene_loader.hpp.
#include <mbd/app/scene_loader.hpp>

#include <mbd/scene.hpp>

namespace mbd {

Model load_with(const SceneLoader& load, const std::filesystem::path& file, Registry& registry) {
    return load ? load(file, registry) : load_scene(file, registry);
}

}  // namespace mbd
