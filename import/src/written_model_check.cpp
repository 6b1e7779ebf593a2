// The exported text read back by its own parser (model_writers.hpp): a file is written only when
// MuJoCo's compiler or urdfdom accepts it.
#include <mbd/import/model_writers.hpp>

#include <mbd/sdk/params.hpp>  // InputError

#include <mujoco/mujoco.h>
#include <urdf_parser/urdf_parser.h>

#include <cctype>
#include <cstring>
#include <memory>

namespace mbd::import {

void check_written_mjcf(const std::string& text, const std::string& output) {
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    const char* name = "exported.xml";
    if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(text.size())) != 0)
        throw InputError(output, "MuJoCo's in-memory file system refused the written MJCF");
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], text.data(), text.size());
    char error[1000] = "";
    mjModel* model = mj_loadXML(name, vfs.get(), error, sizeof error);
    mj_deleteVFS(vfs.get());
    if (model) {
        mj_deleteModel(model);
        return;
    }
    std::string message = error;
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
    for (char& c : message)
        if (c == '\n') c = ' ';
    throw InputError(output, "MuJoCo's compiler refuses the MJCF the scene would become: " + message +
                                 " (nothing written)");
}

void check_written_urdf(const std::string& text, const std::string& output) {
    if (!urdf::parseURDF(text))
        throw InputError(output, "urdfdom refuses the URDF the scene would become (nothing written)");
}

}  // namespace mbd::import
