// libFuzzer target for the scene loader: any input must either load or be
// refused with mbd::InputError. Any other exception, a crash, a leak or
// undefined behaviour (with the sanitizers) is a finding.
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static mbd::Registry registry;  // the build tree's plugins (beside libmbd_core)
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        // labelled as a file in fuzz/seeds/, so that `base:` finds the seed base scenes
        mbd::Model model = mbd::load_scene_text(text, MBD_FUZZ_SEED_DIR "/fuzz.yaml", registry);
        (void)model.initial_state();
    } catch (const mbd::InputError&) {
        // refused with a message: the expected outcome for bad input
    }
    return 0;
}
