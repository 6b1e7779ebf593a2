// A .glb file read back with tinygltf for the tests (test_viewer, test_flexible_animation): its
// accessors' values, nodes by name, the samples of an animation channel, and a node's world
// transform at a sample (parents' transforms composed; animated paths taken from the samples).
#pragma once

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mbd::test {

struct Glb {
    tinygltf::Model model;

    template <class T>
    std::vector<T> values(int accessor) const {
        const auto& a = model.accessors[accessor];
        const auto& v = model.bufferViews[a.bufferView];
        const int components = tinygltf::GetNumComponentsInType(a.type);
        std::vector<T> out(a.count * components);
        std::memcpy(out.data(), model.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset, out.size() * sizeof(T));
        return out;
    }
    std::vector<float> floats(int accessor) const { return values<float>(accessor); }
    int node(const std::string& name) const {
        for (size_t k = 0; k < model.nodes.size(); ++k)
            if (model.nodes[k].name == name) return static_cast<int>(k);
        return -1;
    }
    // (input, output) of the channel animating `path` of node `index`
    std::pair<std::vector<float>, std::vector<float>> channel(int index, const std::string& path) const {
        for (const auto& animation : model.animations)
            for (const auto& c : animation.channels)
                if (c.target_node == index && c.target_path == path) {
                    const auto& s = animation.samplers[c.sampler];
                    return {floats(s.input), floats(s.output)};
                }
        return {};
    }
    // The node's local transform at sample `sample` (glTF: T * R * S; a channel's sample
    // replaces the node's own value of its path).
    Eigen::Affine3d local(int index, size_t sample) const {
        const tinygltf::Node& n = model.nodes[index];
        Eigen::Vector3d t = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Ones();
        Eigen::Quaterniond r = Eigen::Quaterniond::Identity();
        if (n.translation.size() == 3) t = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
        if (n.rotation.size() == 4) r = Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        if (n.scale.size() == 3) s = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
        if (const auto c = channel(index, "translation").second; !c.empty())
            t = Eigen::Vector3d(c[3 * sample], c[3 * sample + 1], c[3 * sample + 2]);
        if (const auto c = channel(index, "rotation").second; !c.empty())
            r = Eigen::Quaterniond(c[4 * sample + 3], c[4 * sample], c[4 * sample + 1], c[4 * sample + 2]);
        if (const auto c = channel(index, "scale").second; !c.empty())
            s = Eigen::Vector3d(c[3 * sample], c[3 * sample + 1], c[3 * sample + 2]);
        EXPECT_TRUE(n.matrix.empty()) << n.name;  // the writer gives TRS, never a matrix
        Eigen::Affine3d m = Eigen::Affine3d::Identity();
        m.translate(t).rotate(r.normalized()).scale(s);
        return m;
    }
    // The node's world transform at sample `sample`: its parents' local transforms composed.
    Eigen::Affine3d world(int index, size_t sample) const {
        std::map<int, int> parent;
        for (size_t k = 0; k < model.nodes.size(); ++k)
            for (int child : model.nodes[k].children) parent[child] = static_cast<int>(k);
        Eigen::Affine3d m = local(index, sample);
        for (auto it = parent.find(index); it != parent.end(); it = parent.find(it->second))
            m = local(it->second, sample) * m;
        return m;
    }
};

inline Glb load_glb(const std::filesystem::path& file) {
    Glb g;
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&g.model, &error, &warning, file.string())) << error << warning;
    return g;
}

}  // namespace mbd::test
