// The body lists of a model's elements (its joints, or its forces) in one contiguous array,
// MuJoCo's flat model data. Each JointInstance / ForceInstance keeps its own std::vector<int>
// of bodies, allocated while the scene was parsed: where the allocator put those small blocks
// depends on what the parser freed before (a longer scene path alone moved them), and a loop
// over 10,000 joints that reads them from scattered places waits for memory at every joint
// (on a 10,000-link chain that doubled the cost of a step). The evaluation loops read these
// copies instead, in element order.
#pragma once

#include <cstddef>
#include <vector>

namespace mbd {

// One element's bodies (kGround for the ground), a view into ElementBodies.
struct BodyList {
    const int* ids = nullptr;
    int count = 0;

    int size() const { return count; }
    int operator[](int k) const { return ids[k]; }
    const int* begin() const { return ids; }
    const int* end() const { return ids + count; }
};

class ElementBodies {
public:
    ElementBodies() = default;
    // from any sequence of elements with a `bodies` vector (Model::joints, Model::forces)
    template <class Element>
    explicit ElementBodies(const std::vector<Element>& elements) {
        start_.reserve(elements.size() + 1);
        start_.push_back(0);
        for (const Element& e : elements) {
            ids_.insert(ids_.end(), e.bodies.begin(), e.bodies.end());
            start_.push_back(static_cast<int>(ids_.size()));
        }
    }

    BodyList operator[](std::size_t element) const {
        return {ids_.data() + start_[element], start_[element + 1] - start_[element]};
    }

private:
    std::vector<int> start_;  // element e's bodies are ids_[start_[e], start_[e + 1])
    std::vector<int> ids_;
};

}  // namespace mbd
