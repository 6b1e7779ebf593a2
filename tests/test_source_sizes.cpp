// The size limits of the source (no file over 600 lines, no function over 80 outside tests):
// scripts/check-sizes.sh measures every file and function with ctags and fails on one over
// its limit that scripts/size-exceptions.txt does not list, or on a listed one back within it.
// Then the check itself on a scratch tree: a function of 81 lines is caught, one of 80 is not.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

std::string script() { return (mbd::test::source_dir() / "scripts" / "check-sizes.sh").string(); }

// A git tree with one source file: a function whose body has `body_lines` lines.
std::filesystem::path tree_with_function(const std::string& name, int body_lines) {
    const std::filesystem::path root = std::filesystem::temp_directory_path() / ("mbd_sizes_" + name);
    std::filesystem::remove_all(root);
    std::filesystem::create_directories(root / "core");
    std::ofstream out(root / "core" / "f.cpp");
    out << "int f(int x) {\n";
    for (int k = 0; k < body_lines; ++k) out << "    x += " << k << ";\n";
    out << "    return x;\n}\n";
    out.close();
    mbd::test::run_command("cd " + root.string() + " && git init -q . && git add core/f.cpp");
    return root;
}

}  // namespace

TEST(SourceSizes, EveryFileAndFunctionWithinItsLimitOrAKnownException) {
    const mbd::test::CommandResult r = mbd::test::run_command(script() + " " + mbd::test::source_dir().string());
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

TEST(SourceSizes, AFunctionOfEightyOneLinesIsCaughtAndOneOfEightyIsNot) {
    // the function's lines: its signature, the body, the return and the closing brace
    const auto over = tree_with_function("over", 78), within = tree_with_function("within", 77);
    const mbd::test::CommandResult caught = mbd::test::run_command(script() + " " + over.string());
    EXPECT_EQ(caught.exit_code, 1) << caught.out << caught.err;
    EXPECT_NE(caught.out.find("OVER    function core/f.cpp:1 f 81"), std::string::npos) << caught.out;
    const mbd::test::CommandResult passed = mbd::test::run_command(script() + " " + within.string());
    EXPECT_EQ(passed.exit_code, 0) << passed.out << passed.err;
    std::filesystem::remove_all(over);
    std::filesystem::remove_all(within);
}
