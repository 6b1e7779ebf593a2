// The flat body lists of a model's elements (core element_bodies.hpp), which the evaluation
// loops read instead of each element's own vector. Oracle: the elements' own body vectors.
#include "support/test_support.hpp"

#include <mbd/element_bodies.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace {

template <class Element>
void expect_same_lists(const std::vector<Element>& elements) {
    const mbd::ElementBodies flat(elements);
    for (size_t e = 0; e < elements.size(); ++e) {
        const mbd::BodyList list = flat[e];
        ASSERT_EQ(list.size(), static_cast<int>(elements[e].bodies.size())) << "element " << e;
        EXPECT_EQ(std::vector<int>(list.begin(), list.end()), elements[e].bodies) << "element " << e;
    }
}

struct Element {
    std::vector<int> bodies;
};

TEST(ElementBodies, ListsOfEveryLengthInElementOrder) {
    // empty, one body, the ground, a body twice, many bodies
    expect_same_lists(std::vector<Element>{{{}}, {{4}}, {{mbd::kGround, 2}}, {{3, 3}}, {{0, 1, 2, 3, 4, 5, 6}}, {{}}});
    expect_same_lists(std::vector<Element>{});
}

TEST(ElementBodies, JointsAndForcesOfAScene) {
    const mbd::Model model = mbd::test::load("four-bar.yaml");
    ASSERT_FALSE(model.joints.empty());
    ASSERT_GE(model.forces.size(), 2u);  // gravity spans every body; the spring two
    expect_same_lists(model.joints);
    expect_same_lists(model.forces);
}

}  // namespace
