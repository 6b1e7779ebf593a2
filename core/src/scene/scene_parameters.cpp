// Scalar scene keys addressed by a path (scene_parameters.hpp).
#include <mbd/scene_parameters.hpp>

#include <mbd/sdk/suggest.hpp>

#include "scene/scene_loader.hpp"
#include "scene/scene_source.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mbd {
namespace {

struct Segment {
    std::string key;           // may be empty for a leading "[i]" (never at the start)
    std::vector<long> indices;
};

[[noreturn]] void path_error(const Param& at, const std::string& path, const std::string& message) {
    throw ParameterError(at.location(), "parameter '" + path + "': " + message, path);
}

bool whole_number(const std::string& text) {
    if (text.empty() || text.size() > 9) return false;
    for (char c : text)
        if (c < '0' || c > '9') return false;
    return true;
}

std::vector<Segment> parse_path(const Param& document, const std::string& path) {
    std::vector<Segment> segments;
    if (path.empty()) path_error(document, path, "the path is empty (for example bodies.crank.mass)");
    size_t k = 0;
    while (k <= path.size()) {
        Segment segment;
        while (k < path.size() && path[k] != '.' && path[k] != '[') segment.key += path[k++];
        while (k < path.size() && path[k] == '[') {
            const size_t close = path.find(']', k);
            const std::string index = close == std::string::npos ? std::string() : path.substr(k + 1, close - k - 1);
            if (!whole_number(index))
                path_error(document, path, "'[" + index + "' is not an index; write [0], [1], ... after a key");
            segment.indices.push_back(std::stol(index));
            k = close + 1;
        }
        if (segment.key.empty())
            path_error(document, path, "an empty key; separate keys with single dots (bodies.crank.mass)");
        segments.push_back(std::move(segment));
        if (k == path.size()) break;
        if (path[k] != '.') path_error(document, path, "expected '.' or '[' after '" + segments.back().key + "'");
        ++k;
        if (k == path.size()) path_error(document, path, "the path ends with '.'");
    }
    return segments;
}

std::string element_name(const Param& item) {
    if (!item.is_map()) return {};
    auto name = item.fields.find("name");
    return name != item.fields.end() && name->second.is_scalar() ? name->second.text : std::string();
}

std::string near_names(const std::string& wanted, const std::vector<std::string>& names) {
    std::string listed;
    for (const auto& n : names) listed += (listed.empty() ? "" : ", ") + n;
    const std::string nearest = nearest_name(wanted, names);
    std::string out = nearest.empty() ? std::string() : "did you mean '" + nearest + "'? ";
    return out + (names.empty() ? "(there are none)" : "(there: " + listed + ")");
}

// The element of a list named by a segment: a position or the value of its `name`.
Param* list_element(Param& list, const std::string& key, const std::string& path, const std::string& where) {
    if (whole_number(key)) {
        const long index = std::stol(key);
        if (index >= static_cast<long>(list.items.size()))
            path_error(list, path, "'" + where + "' has " + std::to_string(list.items.size()) + " items, no item " + key);
        return &list.items[static_cast<size_t>(index)];
    }
    std::vector<std::string> names;
    for (auto& item : list.items) {
        if (element_name(item) == key) return &item;
        if (!element_name(item).empty()) names.push_back(element_name(item));
    }
    path_error(list, path, "no element named '" + key + "' in '" + where + "'; " + near_names(key, names));
}

Param zeros(const Param& owner, int count) {
    Param list;
    list.kind = Param::Kind::List;
    list.file = owner.file;
    list.line = owner.line;
    for (int k = 0; k < count; ++k) {
        Param zero;
        zero.text = "0";
        zero.file = owner.file;
        zero.line = owner.line;
        list.items.push_back(zero);
    }
    return list;
}

// The node at `path`; with `create`, a missing last key (or vector key) is added.
Param* resolve(Param& document, const std::string& path, bool create) {
    const std::vector<Segment> segments = parse_path(document, path);
    auto dimension = document.fields.find("dimension");
    const int vector_size = dimension != document.fields.end() && dimension->second.text == "spatial" ? 3 : 2;
    Param* node = &document;
    std::string where;
    for (size_t s = 0; s < segments.size(); ++s) {
        const Segment& segment = segments[s];
        const bool last = s + 1 == segments.size();
        if (node->is_list()) {
            node = list_element(*node, segment.key, path, where);
        } else if (node->is_map()) {
            auto field = node->fields.find(segment.key);
            if (field == node->fields.end()) {
                std::vector<std::string> keys;
                for (const auto& kv : node->fields) keys.push_back(kv.first);
                const bool creatable = create && last && segment.indices.size() <= 1 &&
                                       (segment.indices.empty() || segment.indices[0] < vector_size);
                if (!creatable)
                    path_error(*node, path, "no key '" + segment.key + "' " +
                                                (where.empty() ? "at the top of the scene" : "in '" + where + "'") +
                                                "; " + near_names(segment.key, keys));
                Param added = segment.indices.empty() ? Param() : zeros(*node, vector_size);
                added.file = node->file;
                added.line = node->line;
                field = node->fields.emplace(segment.key, std::move(added)).first;
            }
            node = &field->second;
        } else {
            path_error(*node, path, "'" + where + "' is a number, it has no key '" + segment.key + "'");
        }
        where += (where.empty() ? "" : ".") + segment.key;
        for (long index : segment.indices) {
            if (!node->is_list())
                path_error(*node, path, "'" + where + "' is not a list, so [" + std::to_string(index) + "] is not there");
            if (index >= static_cast<long>(node->items.size()))
                path_error(*node, path, "'" + where + "' has " + std::to_string(node->items.size()) + " items, no [" +
                                            std::to_string(index) + "]");
            node = &node->items[static_cast<size_t>(index)];
            where += "[" + std::to_string(index) + "]";
        }
    }
    if (!node->is_scalar())
        path_error(*node, path, "'" + where + "' is a " + (node->is_list() ? "list" : "map") +
                                    "; address one number in it" + (node->is_list() ? " with [i]" : " by its key"));
    return node;
}

}  // namespace

double scene_parameter(const Param& document, const std::string& path) {
    Param copy = document;  // resolve() walks a mutable tree; reading changes nothing
    const Param* node = resolve(copy, path, false);
    return node->as_number(path);
}

void set_scene_parameter(Param& document, const std::string& path, double value) {
    if (!std::isfinite(value))
        path_error(document, path, "the value must be a finite number, got " + format_number(value));
    Param* node = resolve(document, path, true);
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    node->text = text;
}

Param read_scene_document(const std::filesystem::path& file) {
    detail::SceneTreeReader reader;
    const std::string label = file.string();
    return reader.with_base(reader.convert(reader.parse(detail::read_scene_file(file), label), label), label);
}

namespace {

// A path segment for `item` of a list: its name when it has one that resolves to it (the
// first item of that name), else its position.
std::string item_segment(const Param& list, size_t index) {
    const std::string name = element_name(list.items[index]);
    if (!name.empty() && !whole_number(name))
        for (size_t k = 0; k < list.items.size(); ++k)
            if (element_name(list.items[k]) == name) return k == index ? name : std::to_string(index);
    return std::to_string(index);
}

// Depth-first, keys in their (alphabetical) map order; `path` is the node's path. Items of a
// list are written `key.name` (or `key.i`) when they are maps (elements), `key[i]` otherwise.
bool find_key_at(const Param& node, const std::string& file, int line, const std::string& path, std::string& found) {
    // a list of elements starts where its first element does: the element is the more precise
    const bool list_of_elements = node.is_list() && !node.items.empty() && node.items[0].is_map();
    if (!path.empty() && node.line == line && node.file == file && !list_of_elements) {
        found = path;
        return true;
    }
    if (node.is_map()) {
        for (const auto& [key, child] : node.fields)
            if (find_key_at(child, file, line, path.empty() ? key : path + "." + key, found)) return true;
    } else if (node.is_list()) {
        for (size_t k = 0; k < node.items.size(); ++k) {
            const Param& item = node.items[k];
            const std::string segment =
                item.is_map() ? "." + item_segment(node, k) : "[" + std::to_string(k) + "]";
            if (find_key_at(item, file, line, path + segment, found)) return true;
        }
    }
    return false;
}

}  // namespace

std::string scene_key_at(const Param& document, const std::string& file, int line) {
    std::string found;
    find_key_at(document, file, line, "", found);
    return found;
}

Model load_scene_document(const Param& document, const std::string& label, Registry& registry) {
    scene_detail::Loader loader(label, registry);
    return loader.load_document(document);
}

Model with_scene_parameters(const Model& model, const SceneParameterValues& values, Registry& registry) {
    if (!model.document) throw InputError(model.source, "this model keeps no scene document to change");
    Param document = *model.document;
    std::string changes;
    for (const auto& [path, value] : values) {
        set_scene_parameter(document, path, value);
        changes += (changes.empty() ? "" : ", ") + path + " = " + format_number(value, 10);
    }
    try {
        Model changed = load_scene_document(document, model.source, registry);
        changed.base_files = model.base_files;
        return changed;
    } catch (const InputError& e) {
        // the scene is valid as written, so the parameters made it invalid: say which
        rethrow_input_error(e, e.message() + " (with " + changes + ")");
    }
}

}  // namespace mbd
