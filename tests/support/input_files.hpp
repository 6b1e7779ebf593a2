// Bad-input tests: input files written into a scratch folder, and the message of the InputError a
// call throws.
#pragma once

#include "support/test_support.hpp"

#include <mbd/sdk/params.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>

namespace mbd::test {

// `text` as the file `name` in this process's scratch folder `folder` (made fresh on first use, so
// the files of one test program stay side by side); returns its path.
inline std::filesystem::path write_scratch_file(const std::string& folder, const std::string& name,
                                                const std::string& text) {
    static std::map<std::string, std::filesystem::path> folders;
    auto it = folders.find(folder);
    if (it == folders.end()) it = folders.emplace(folder, scratch(folder)).first;
    return write_text(it->second / name, text);
}

// The message of the InputError `fn` throws, or "(accepted)" when it throws none.
inline std::string input_error_of(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

}  // namespace mbd::test
