// Formulation plugins of another formulation kit ABI, as a formulation built against a past
// or future kit would be: one claims kit ABI 999, one was registered with the element
// plugins' ABI (MBD_ABI_VERSION, sdk plugin.hpp) instead of the kit's. The registry must list
// both and refuse them with a message naming the kit, without loading the library.
// A fixture, not a test program: it holds no assertion itself; its library is read by
// Registry.FormulationOfAnotherKitAbiIsListedAndRefusedWithAClearMessage (tests/test_registry.cpp),
// which asserts each type's recorded ABI, its absence from the usable formulations and both refusals.
#include <mbd/kit/formulation.hpp>

static_assert(MBD_ABI_VERSION != MBD_KIT_ABI_VERSION,
              "this test plugin needs the SDK's ABI to differ from the kit's (bump one of them)");

namespace {

std::unique_ptr<mbd::Formulation> make_old_formulation(const mbd::FormulationSpec&) { return nullptr; }

}  // namespace

BOOST_DLL_ALIAS_SECTIONED(make_old_formulation, mbd_abi999__formulation__old_formulation, mbdplug)
MBD_REGISTER_PLUGIN(formulation, sdk_abi_formulation, make_old_formulation)
