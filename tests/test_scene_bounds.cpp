// The scene reader bounds what it reads (docs/scene-format.md, Limits): regular files only,
// at most SceneLimits::max_file_bytes, YAML alias cycles refused, alias expansion and
// nesting depth bounded. Each refusal is an InputError naming the file (and line), through
// the library and through the mbd command (exit 2, no crash, no hang).
#include <mbd/scene.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::SceneLimits;
using mbd::test::run_command;
using mbd::test::scratch;

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

// The message of the InputError a scene text is refused with.
std::string text_error(const std::string& yaml) {
    try {
        mbd::load_scene_text(yaml, "test.yaml", mbd::test::shared_registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError, the scene loaded";
    return {};
}

std::string file_error(const fs::path& file) {
    try {
        mbd::load_scene(file, mbd::test::shared_registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError, " << file << " loaded";
    return {};
}

// `mbd check FILE` under coreutils' timeout: a hang shows as status 124 instead of
// stalling the suite; a crash as a signal status (>= 128).
mbd::test::CommandResult check_command(const fs::path& file) {
    return run_command("timeout 60 '" + std::string(MBD_EXECUTABLE) + "' check '" + file.string() + "'");
}

// `named` is the file the message must name (default: the scene given).
void expect_refused_by_cli(const fs::path& file, const std::string& part, const fs::path& named = {}) {
    const auto r = check_command(file);
    EXPECT_EQ(r.exit_code, 2) << "stderr: " << r.err;
    EXPECT_CONTAINS(r.err, "mbd: error: ");
    EXPECT_CONTAINS(r.err, (named.empty() ? file : named).string());
    EXPECT_CONTAINS(r.err, part);
}

// A valid planar scene: one pendulum.
const std::string kPendulum = R"(dimension: planar
bodies:
  - {name: link, mass: 1, inertia: 0.1, position: [0.5, 0]}
joints:
  - {name: pin, type: revolute, bodies: [ground, link], point: [0, 0]}
)";

// The classic exponential alias document: each level lists the previous one nine
// times, so 9 levels expand to 9^9 (about 387 million) values from under 700 bytes.
std::string alias_bomb() {
    std::string text = "a0: &a0 [\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\"]\n";
    for (int level = 1; level <= 8; ++level) {
        const std::string previous = "*a" + std::to_string(level - 1);
        text += "a" + std::to_string(level) + ": &a" + std::to_string(level) + " [";
        for (int k = 0; k < 9; ++k) text += (k ? "," : "") + previous;
        text += "]\n";
    }
    return text;
}

}  // namespace

TEST(SceneBounds, SelfReferencingAliasIsACycleAtItsLine) {
    for (const std::string yaml : {std::string("x: &a [*a]\n"), std::string("dimension: planar\nx: &m {y: *m}\n"),
                                   kPendulum + "joint_list: &j [1, [2, *j]]\n"}) {
        const std::string msg = text_error(yaml);
        EXPECT_CONTAINS(msg, "test.yaml:");
        EXPECT_CONTAINS(msg, "contains it");
    }
    // the anchored list starts at line 6 of the third scene
    EXPECT_CONTAINS(text_error(kPendulum + "joint_list: &j [1, [2, *j]]\n"), "test.yaml:6");
}

TEST(SceneBounds, AliasesWithinTheBoundsLoad) {
    // an anchor reused by several bodies: each body gets the anchored values
    const mbd::Model model = mbd::test::scene(R"(dimension: spatial
bodies:
  - {name: a, mass: 2, inertia: &box [0.1, 0.2, 0.25], position: [0, 0, 0]}
  - {name: b, mass: 2, inertia: *box, position: [1, 0, 0]}
)");
    ASSERT_EQ(model.body_count(), 2);
    EXPECT_DOUBLE_EQ(model.bodies[1].inertia(0, 0), 0.1);
    EXPECT_DOUBLE_EQ(model.bodies[1].inertia(1, 1), 0.2);
    EXPECT_DOUBLE_EQ(model.bodies[1].inertia(2, 2), 0.25);
}

TEST(SceneBounds, AliasBombIsRefusedByItsExpandedSize) {
    const std::string bomb = alias_bomb();
    ASSERT_LT(bomb.size(), 700u);
    const std::string msg = text_error(bomb);
    EXPECT_CONTAINS(msg, "test.yaml:");
    EXPECT_CONTAINS(msg, "more than " + std::to_string(SceneLimits::max_values) + " values");
    EXPECT_CONTAINS(msg, "aliases");

    const fs::path file = write_text(scratch("bomb") / "bomb.yaml", bomb);
    EXPECT_CONTAINS(file_error(file), file.string() + ":");
    expect_refused_by_cli(file, "aliases are expanded");
}

TEST(SceneBounds, NestingDepthIsLimited) {
    auto nested = [](int depth) { return "x: " + std::string(depth, '[') + std::string(depth, ']') + "\n"; };
    // one level within the limit converts (and is refused later as no scene, not for depth)
    EXPECT_EQ(text_error(nested(SceneLimits::max_depth - 1)).find("nested more than"), std::string::npos);
    const std::string msg = text_error(nested(SceneLimits::max_depth + 1));
    EXPECT_CONTAINS(msg, "test.yaml:1");
    EXPECT_CONTAINS(msg, "nested more than " + std::to_string(SceneLimits::max_depth));
    // far deeper than any limit: refused by the YAML parser's own guard, as a syntax error, no stack overflow
    const std::string deep = text_error(nested(100000));
    EXPECT_CONTAINS(deep, "test.yaml:1");
    EXPECT_CONTAINS(deep, "YAML syntax error");
}

TEST(SceneBounds, AliasCycleInsideABaseFileNamesTheBase) {
    const fs::path dir = scratch("base-alias");
    write_text(dir / "base.yaml", kPendulum + "notes: &n [a, *n]\n");
    const fs::path derived = write_text(dir / "derived.yaml", "base: base.yaml\nname: d\n");
    const std::string msg = file_error(derived);
    EXPECT_CONTAINS(msg, (dir / "base.yaml").string() + ":6");
    EXPECT_CONTAINS(msg, "contains it");
    expect_refused_by_cli(derived, "contains it", dir / "base.yaml");
    // an alias bomb in the base: the base file is named too
    write_text(dir / "bomb.yaml", alias_bomb());
    const std::string bomb = file_error(write_text(dir / "uses-bomb.yaml", "base: bomb.yaml\n"));
    EXPECT_CONTAINS(bomb, (dir / "bomb.yaml").string() + ":");
    EXPECT_CONTAINS(bomb, "aliases are expanded");
}

TEST(SceneBounds, DevZeroIsNotAScene) {
    const std::string msg = file_error("/dev/zero");
    EXPECT_CONTAINS(msg, "/dev/zero");
    EXPECT_CONTAINS(msg, "character device");
    expect_refused_by_cli("/dev/zero", "character device");
    const fs::path derived = write_text(scratch("base-zero") / "derived.yaml", "name: d\nbase: /dev/zero\n");
    const std::string base = file_error(derived);
    EXPECT_CONTAINS(base, derived.string() + ":2");
    EXPECT_CONTAINS(base, "'/dev/zero'");
    EXPECT_CONTAINS(base, "character device");
}

TEST(SceneBounds, FifoIsRefusedWithoutWaitingForAWriter) {
    const fs::path dir = scratch("fifo");
    const fs::path fifo = dir / "scene.yaml";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string msg = file_error(fifo);  // returns: no writer ever opens the FIFO
    EXPECT_CONTAINS(msg, fifo.string());
    EXPECT_CONTAINS(msg, "FIFO");
    expect_refused_by_cli(fifo, "FIFO");
    const std::string base = file_error(write_text(dir / "derived.yaml", "base: scene.yaml\n"));
    EXPECT_CONTAINS(base, (dir / "derived.yaml").string() + ":1");
    EXPECT_CONTAINS(base, fifo.string());
    EXPECT_CONTAINS(base, "FIFO");
}

TEST(SceneBounds, DirectoryIsNotAScene) {
    const fs::path dir = scratch("directory");
    fs::create_directories(dir / "scene.yaml");
    const std::string msg = file_error(dir / "scene.yaml");
    EXPECT_CONTAINS(msg, (dir / "scene.yaml").string());
    EXPECT_CONTAINS(msg, "a directory");
    expect_refused_by_cli(dir / "scene.yaml", "a directory");
    const std::string base = file_error(write_text(dir / "derived.yaml", "base: scene.yaml\n"));
    EXPECT_CONTAINS(base, (dir / "derived.yaml").string() + ":1");
    EXPECT_CONTAINS(base, "a directory");
}

TEST(SceneBounds, OversizedFileIsRefusedBeforeParsing) {
    const fs::path dir = scratch("oversized");
    // a valid scene padded with a comment to one byte over the limit
    std::string text = kPendulum + "# ";
    text += std::string(SceneLimits::max_file_bytes + 1 - text.size() - 1, 'x') + "\n";
    ASSERT_EQ(text.size(), SceneLimits::max_file_bytes + 1);
    const fs::path big = write_text(dir / "big.yaml", text);
    const std::string msg = file_error(big);
    EXPECT_CONTAINS(msg, big.string());
    EXPECT_CONTAINS(msg, "16.0 MiB");
    expect_refused_by_cli(big, "at most 16.0 MiB");
    const std::string base = file_error(write_text(dir / "derived.yaml", "base: big.yaml\n"));
    EXPECT_CONTAINS(base, (dir / "derived.yaml").string() + ":1");
    EXPECT_CONTAINS(base, "at most 16.0 MiB");
    EXPECT_CONTAINS(text_error(text), "at most 16.0 MiB");
    // exactly at the limit the file is read (and loads: the padding is a comment)
    text.erase(text.size() - 2, 1);
    ASSERT_EQ(text.size(), SceneLimits::max_file_bytes);
    EXPECT_EQ(mbd::load_scene(write_text(dir / "limit.yaml", text), mbd::test::shared_registry()).body_count(), 1);
}

TEST(SceneBounds, MissingFileIsNamed) {
    const fs::path missing = scratch("missing") / "nowhere.yaml";
    const std::string msg = file_error(missing);
    EXPECT_CONTAINS(msg, missing.string());
    EXPECT_CONTAINS(msg, "no such file");
    expect_refused_by_cli(missing, "no such file");
}
