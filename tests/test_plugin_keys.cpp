// The keys plugin types describe (mbd/sdk/plugin_keys.hpp): every shipped joint and force
// type describes them, `mbd plugin check` checks every type with no flags from the description
// alone, and docs/scene-format.md agrees with the descriptions both ways.
#include "support/test_support.hpp"

#include <mbd/plugin_description.hpp>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>

namespace mbd {
namespace {

struct Listed {
    std::string kind, type;
};

// The joint and force types `mbd plugins` lists (the build's plugin folder).
std::vector<Listed> listed_types() {
    const auto r = test::run_mbd("plugins");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    std::vector<Listed> types;
    std::istringstream in(r.out);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        Listed t;
        words >> t.kind >> t.type;
        if (t.kind == "joint" || t.kind == "force") types.push_back(t);
    }
    return types;
}

TEST(PluginKeys, EveryShippedJointAndForceTypeDescribesItsKeys) {
    const std::vector<Listed> types = listed_types();
    // the 17 joint and 14 force types shipped (issue 42 counted 29; issue 39 added collision_contact, issue 37
    // coordinate_coupling)
    EXPECT_EQ(types.size(), 31u);
    for (const Listed& t : types) {
        const PluginDescription* d = plugin_description(test::shared_registry(), t.kind, t.type);
        ASSERT_NE(d, nullptr) << t.kind << " " << t.type;
        EXPECT_TRUE(d->summary && *d->summary) << t.type;
        EXPECT_EQ(d->bodies, t.type == "gravity" || t.type == "collision_contact" ? kEveryBody
                             : t.type == "point_force" || t.type == "point_torque" ? kOneBody
                                                                                    : kTwoBodies)
            << t.type;
        std::set<std::string> names;
        for (int k = 0; k < d->key_count(); ++k) {
            const PluginKey& key = d->keys[k];
            EXPECT_TRUE(names.insert(key.name).second) << t.type << ": key '" << key.name << "' described twice";
            EXPECT_TRUE(key.meaning && *key.meaning) << t.type << "." << key.name;
            EXPECT_TRUE(key.example && *key.example) << t.type << "." << key.name << ": no example value";
        }
    }
}

// The acceptance test of issue 42: every joint and force type `mbd plugins` lists passes
// `mbd plugin check TYPE` with no flags, two-body elements checked between two moving bodies.
TEST(PluginKeys, PluginCheckPassesEveryTypeWithNoFlags) {
    for (const Listed& t : listed_types()) {
        const auto r = test::run_mbd("plugin check " + t.type);
        EXPECT_EQ(r.exit_code, 0) << t.type << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find(" 0 failed"), std::string::npos) << r.out;
        EXPECT_EQ(r.out.find("0 checked"), std::string::npos) << t.type << ": nothing was checked\n" << r.out;
        EXPECT_EQ(r.out.find("note "), std::string::npos) << r.out;
        const PluginDescription* d = plugin_description(test::shared_registry(), t.kind, t.type);
        ASSERT_NE(d, nullptr);
        if (d->bodies == kTwoBodies)  // between the bodies a and b, both moving
            EXPECT_NE(r.out.find("[a, b]"), std::string::npos) << t.type << "\n" << r.out;
        if (d->bodies == kOneBody) EXPECT_NE(r.out.find("[a]"), std::string::npos) << t.type << "\n" << r.out;
    }
}

TEST(PluginKeys, PluginCheckOfAnUnknownTypeNamesTheKnownOnes) {
    const auto r = test::run_mbd("plugin check scruw");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("'scruw' is neither a plugin library file nor a joint or force type"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("screw"), std::string::npos) << r.out;
}

TEST(PluginKeys, PluginsKeysPrintsTheTable) {
    const auto r = test::run_mbd("plugins --keys screw");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("| `pitch` | travel along the axis per revolution (m), non-zero; positive: right-handed | required | "
                         "`0.02` |"),
              std::string::npos)
        << r.out;
    const auto none = test::run_mbd("plugins --keys no_such_type");
    EXPECT_EQ(none.exit_code, 2);
    EXPECT_NE(none.err.find("no joint or force type 'no_such_type'"), std::string::npos) << none.err;
}

// ------------------------------------------------------------------ docs/scene-format.md

// The text of the sections of docs/scene-format.md that document a type: a joint's paragraphs
// opening with **type**, a force's ### headings naming it; each runs to the next heading or
// to the next paragraph opening with another joint type.
std::string doc_sections(const std::vector<std::string>& lines, const Listed& t, const std::set<std::string>& joints) {
    const std::regex word("(^|[^a-z_])" + t.type + "([^a-z_]|$)");
    std::string text;
    bool inside = false, code = false;
    for (const std::string& line : lines) {
        if (line.rfind("```", 0) == 0) code = !code;
        const bool heading = !code && line.rfind("#", 0) == 0;  // a YAML comment is no heading
        bool other_joint = false;
        if (line.rfind("**", 0) == 0) {
            const size_t end = line.find("**", 2);
            other_joint = end != std::string::npos && joints.count(line.substr(2, end - 2));
        }
        if (heading || other_joint) {
            inside = t.kind == "joint" ? line.rfind("**" + t.type + "**", 0) == 0
                                       : line.rfind("### ", 0) == 0 && std::regex_search(line, word);
        }
        if (inside) text += line + "\n";
    }
    return text;
}

// Whether `key` is written in backquotes in `text`: `key` or `key: ...`.
bool backquoted(const std::string& text, const std::string& key) {
    return text.find("`" + key + "`") != std::string::npos || text.find("`" + key + ":") != std::string::npos;
}

// The top-level keys of every element of type `type` in the YAML blocks of `text`.
std::set<std::string> example_keys(const std::string& text, const std::string& type) {
    std::set<std::string> keys;
    const std::regex block("```yaml\n([\\s\\S]*?)```");
    for (std::sregex_iterator it(text.begin(), text.end(), block), end; it != end; ++it) {
        const YAML::Node items = YAML::Load((*it)[1].str());
        if (!items.IsSequence()) continue;
        for (const YAML::Node& item : items)
            if (item.IsMap() && item["type"] && item["type"].as<std::string>() == type)
                for (const auto& kv : item) keys.insert(kv.first.as<std::string>());
    }
    return keys;
}

TEST(PluginKeys, SceneFormatDocumentsEveryDescribedKeyAndNoOther) {
    std::vector<std::string> lines;
    {
        std::istringstream in(test::read_text(test::source_dir() / "docs/scene-format.md"));
        std::string line;
        while (std::getline(in, line)) lines.push_back(line);
    }
    const std::vector<Listed> types = listed_types();
    std::set<std::string> joints;
    for (const Listed& t : types)
        if (t.kind == "joint") joints.insert(t.type);
    const std::set<std::string> core_joint{"name", "type", "bodies", "point", "axis", "x_axis", "axes", "limits"};
    const std::set<std::string> core_force{"name", "type", "body", "bodies", "point", "points", "axis", "x_axis"};
    int sections = 0, keys_checked = 0;
    for (const Listed& t : types) {
        const std::string text = doc_sections(lines, t, joints);
        EXPECT_FALSE(text.empty()) << "docs/scene-format.md has no section for " << t.kind << " '" << t.type << "'";
        if (text.empty()) continue;
        ++sections;
        const PluginDescription* d = plugin_description(test::shared_registry(), t.kind, t.type);
        ASSERT_NE(d, nullptr) << t.type;
        for (const std::string& key : key_names(*d)) {
            ++keys_checked;
            EXPECT_TRUE(backquoted(text, key))
                << t.kind << " '" << t.type << "' describes key '" << key << "', which its section of "
                << "docs/scene-format.md does not mention:\n" << text;
        }
        const std::set<std::string>& core = t.kind == "joint" ? core_joint : core_force;
        for (const std::string& key : example_keys(text, t.type))
            EXPECT_TRUE(core.count(key) || d->find(key.c_str()))
                << "docs/scene-format.md's example of " << t.kind << " '" << t.type << "' uses key '" << key
                << "', which the type does not describe";
    }
    EXPECT_EQ(sections, 31);
    EXPECT_GT(keys_checked, 60);
}

// The check above would catch a key missing from the docs: a section without `pitch` fails.
TEST(PluginKeys, TheDocumentationCheckSeesAMissingKey) {
    const std::vector<std::string> lines{"**screw** (5 rows): plugin key `pitch` = travel", "```yaml",
                                         "# a comment", "- {name: s, type: screw, bodies: [ground, nut], pitch: 0.01, lead: 2}",
                                         "```", "**revolute** (2 rows)"};
    const std::string text = doc_sections(lines, {"joint", "screw"}, {"screw", "revolute"});
    EXPECT_TRUE(backquoted(text, "pitch"));
    EXPECT_FALSE(backquoted(text, "lead"));
    EXPECT_EQ(text.find("revolute"), std::string::npos) << text;
    EXPECT_EQ(example_keys(text, "screw"), (std::set<std::string>{"name", "type", "bodies", "pitch", "lead"}));
}

}  // namespace
}  // namespace mbd
