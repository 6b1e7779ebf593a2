// A joint plugin that claims an ABI this mbd does not speak (999), as a plugin
// built against a future or past SDK would. The registry must list it and
// refuse it with a message, without loading it.
#include <mbd/sdk/plugin.hpp>

namespace {

struct OldJoint : mbd::Joint {
    int rows() const override { return 1; }
    void evaluate(const mbd::BodyStates&, mbd::ConstraintEval&) const override {}
};

std::unique_ptr<mbd::Joint> make_old_joint(const mbd::JointSpec&) { return std::make_unique<OldJoint>(); }

}  // namespace

BOOST_DLL_ALIAS_SECTIONED(make_old_joint, mbd_abi999__joint__old_joint, mbdplug)
