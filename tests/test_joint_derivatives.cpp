// One generic test over every joint type the registry finds, planar and
// spatial: the Jacobian matches central finite differences of C, and gamma
// matches the second time derivative of C along random smooth trajectories
// (Cddot = J vdot - gamma), at states that do NOT satisfy the constraints. The
// same checks run on the joint coordinate that drivers prescribe, and on the velocity-level
// rows (d/dt (A v - b) = A vdot - gamma along the trajectories). A joint type
// is exercised through the example scenes in scenes/examples/ that use it, so a
// new joint type gets this test by shipping an example, without writing a test.
// Each example runs as written and with random joint geometry (random marker
// offsets, axes and `points`; with_random_joint_geometry), seeded, so that no term
// is hidden by a marker at a mass centre or an axis along a coordinate axis.
#include "support/test_support.hpp"

#include <mbd/derivative_check.hpp>
#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/text.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

namespace mbd {
namespace {

TEST(JointDerivatives, EveryRegisteredJointTypeMatchesFiniteDifferences) {
    Registry& registry = test::shared_registry();
    const std::vector<std::string> types = registry.type_names("joint");
    ASSERT_GE(types.size(), 10u) << "expected at least the 10 standard joint types";

    // which (type, dimension) pairs the example scenes cover
    std::map<std::string, std::set<std::string>> covered;
    constexpr int kRandomGeometries = 3;
    constexpr int kDrawsOutsideTheDomain = 200;
    std::mt19937 rng(20261121);
    // the checks of one scene's joints
    auto check_scene = [&](const std::string& yaml, const std::string& file, const char* variant) {
        const Model model = load_scene_text(yaml, file, registry);
        for (const JointInstance& ji : model.joints) {
            SCOPED_TRACE("joint '" + ji.name + "' of type " + ji.type);
            const DerivativeErrors c = check_joint_derivatives(model, ji, rng);
            std::printf("%-10s %-12s %-14s %-9s J %.1e  gamma %.1e  C_t %.1e  J_s %.1e  gamma_s %.1e  gamma_v %.1e  "
                        "dgamma/dv^T %s\n",
                        to_string(model.dimension), ji.type.c_str(), ji.name.c_str(), variant, c.jacobian, c.gamma,
                        c.time_derivative, c.coordinate_jacobian, c.coordinate_gamma, c.velocity_gamma,
                        ji.joint->has_gamma_velocity_transpose() ? format_number(c.gamma_velocity_transpose).c_str() : "-");
            EXPECT_LT(c.jacobian, 1e-6);
            EXPECT_LT(c.gamma, 1e-6);
            EXPECT_LT(c.time_derivative, 1e-6);
            EXPECT_LT(c.coordinate_jacobian, 1e-6);
            EXPECT_LT(c.coordinate_gamma, 1e-6);
            EXPECT_LT(c.velocity_gamma, 1e-6);
            // exact up to round-off (gamma is quadratic in v)
            EXPECT_LT(c.gamma_velocity_transpose, 1e-10);
            EXPECT_LT(c.velocity_dependence, 1e-12);
            covered[ji.type].insert(to_string(model.dimension));
        }
    };
    for (const auto& entry : std::filesystem::directory_iterator(test::scene_path("examples"))) {
        if (entry.path().extension() != ".yaml") continue;
        const std::string file = entry.path().string();
        const std::string text = test::read_text(entry.path());
        {
            SCOPED_TRACE(file + " as written");
            check_scene(text, file, "as given");
        }
        for (int k = 0; k < kRandomGeometries; ++k) {
            // a draw that puts a joint where its geometry is not defined (a wheel whose tread is
            // nowhere over its rail, DomainError) checks nothing: that geometry is drawn again
            for (int draw = 1;; ++draw) {
                const std::string yaml = with_random_joint_geometry(text, rng);
                SCOPED_TRACE(file + " with random joint geometry:\n" + yaml);
                try {
                    check_scene(yaml, file, "random");
                    break;
                } catch (const DomainError& e) {
                    if (draw == kDrawsOutsideTheDomain) {
                        ADD_FAILURE() << kDrawsOutsideTheDomain << " random geometries all left a joint's domain: " << e.what();
                        break;
                    }
                }
            }
        }
    }
    // every registered type must be exercised in at least one dimension
    for (const std::string& type : types)
        EXPECT_TRUE(covered.count(type)) << "joint type '" << type
                                         << "' has no example scene in scenes/examples/; add one so this test covers it";
    // the types that exist in both dimensions must be covered in both
    for (const std::string& type : {"revolute", "prismatic", "fixed"}) {
        EXPECT_TRUE(covered[type].count("planar")) << type;
        EXPECT_TRUE(covered[type].count("spatial")) << type;
    }
}

}  // namespace
}  // namespace mbd
