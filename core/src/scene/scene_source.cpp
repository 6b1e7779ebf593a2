// Bounded reading of scene files and their YAML (see scene_source.hpp).
#include "scene/scene_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <utility>

namespace mbd::detail {
namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string mebibytes(std::uintmax_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1u << 20));
    return text;
}

const char* file_kind(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Closes the descriptor on every path out.
struct FileDescriptor {
    int fd = -1;
    ~FileDescriptor() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::string read_scene_file(const std::filesystem::path& path, const std::string& named_at) {
    const std::string name = path.string();
    auto refuse = [&](const std::string& why) -> std::string {
        if (named_at.empty()) throw InputError(name, "cannot read the scene file: " + why);
        throw InputError(named_at, "cannot read the base scene " + quote(name) + " (the path is relative to this "
                                   "file): " + why);
    };
    // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked on the
    // open descriptor, so the file cannot change between the check and the read.
    FileDescriptor file{::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
    if (file.fd < 0) {
        const int error = errno;
        if (error == ENOENT) return refuse("no such file; check the path");
        return refuse(std::string(std::strerror(error)));
    }
    struct stat info {};
    if (::fstat(file.fd, &info) != 0) return refuse(std::strerror(errno));
    if (!S_ISREG(info.st_mode))
        return refuse(std::string("it is ") + file_kind(info.st_mode) + "; a scene is a regular YAML file");
    const auto size = static_cast<std::uintmax_t>(info.st_size);
    if (size > SceneLimits::max_file_bytes)
        return refuse("it is " + mebibytes(size) + "; a scene file may be at most " +
                      mebibytes(SceneLimits::max_file_bytes) + " (docs/scene-format.md, Limits)");
    std::string text;
    text.reserve(static_cast<size_t>(size));
    char buffer[1 << 16];
    for (;;) {
        const ssize_t got = ::read(file.fd, buffer, sizeof buffer);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) return refuse(std::strerror(errno));
        if (got == 0) break;
        text.append(buffer, static_cast<size_t>(got));
        if (text.size() > SceneLimits::max_file_bytes)  // the file grew while being read
            return refuse("it grew beyond " + mebibytes(SceneLimits::max_file_bytes) + " while being read");
    }
    return text;
}

YAML::Node SceneTreeReader::parse(const std::string& text, const std::string& file) {
    if (text.size() > SceneLimits::max_file_bytes)
        throw InputError(file, "the scene text is " + mebibytes(text.size()) + "; a scene may be at most " +
                                   mebibytes(SceneLimits::max_file_bytes) + " (docs/scene-format.md, Limits)");
    text_ = &text;
    try {
        return YAML::Load(text);
    } catch (const YAML::Exception& e) {
        const int line = e.mark.is_null() ? 1 : e.mark.line + 1;
        const std::string column = e.mark.is_null() ? std::string() : ":" + std::to_string(e.mark.column + 1);
        throw InputError(file + ":" + std::to_string(line), "YAML syntax error at " + file + ":" + std::to_string(line) +
                                                                column + ": " + e.msg + "; fix the YAML syntax there");
    }
}

void SceneTreeReader::require_closed_quote(const YAML::Mark& mark, const std::string& file) const {
    if (!text_ || mark.is_null() || mark.pos < 0 || static_cast<size_t>(mark.pos) >= text_->size()) return;
    const std::string& text = *text_;
    const char quote_char = text[static_cast<size_t>(mark.pos)];
    if (quote_char != '"' && quote_char != '\'') return;  // a block scalar (| or >)
    for (size_t k = static_cast<size_t>(mark.pos) + 1; k < text.size(); ++k) {
        if (quote_char == '"' && text[k] == '\\') {
            ++k;  // an escape: the next character is never the closing quote
        } else if (text[k] == quote_char) {
            if (quote_char == '\'' && k + 1 < text.size() && text[k + 1] == '\'') {
                ++k;  // '' inside single quotes is one quote
            } else {
                return;
            }
        }
    }
    const std::string line = std::to_string(mark.line + 1);
    throw InputError(file + ":" + line, std::string("YAML syntax error at ") + file + ":" + line + ":" +
                                            std::to_string(mark.column + 1) + ": the quoted value opened there (" +
                                            quote_char + ") is never closed, so the YAML reader takes the rest of the "
                                            "file as its text; add the closing " + quote_char);
}

Param SceneTreeReader::convert(const YAML::Node& root, const std::string& file) {
    open_.clear();
    seen_.clear();
    return convert(root, file, 1);
}

Param SceneTreeReader::convert(const YAML::Node& node, const std::string& file, int fallback_line) {
    Param p;
    p.file = file;
    const YAML::Mark mark = node.Mark();
    p.line = mark.is_null() ? fallback_line : mark.line + 1;
    // an alias is the anchored node itself again, at the anchor's text position
    if (!mark.is_null() && !seen_.insert(static_cast<std::size_t>(mark.pos)).second) ++repeats_;
    if (++values_ > SceneLimits::max_values) {
        const std::string limit = std::to_string(SceneLimits::max_values);
        if (repeats_ == 0)
            p.fail("the scene has more than " + limit + " values (each number, name, list and map counts one; a "
                   "body or a joint takes about 10): a scene may have at most " + limit +
                   " values, its base files included (docs/scene-format.md, Limits); split it into smaller scenes");
        p.fail("the scene has more than " + limit + " values once its YAML aliases are expanded (" +
               std::to_string(repeats_) + " of them repeated by aliases; each '*alias' repeats the whole anchored "
               "value, so nested aliases multiply); write the values out or use fewer aliases");
    }
    const bool collection = node.IsSequence() || node.IsMap();
    if (collection) {
        // yaml-cpp shares an anchored node among its aliases, so an alias inside its own
        // anchor is a cycle in the node graph
        for (const YAML::Node& outer : open_)
            if (outer.is(node))
                p.fail("a YAML alias refers to a list or map that contains it (as in 'x: &a [*a]'), which would "
                       "repeat without end; an alias may only repeat a value defined before and outside it");
        if (static_cast<int>(open_.size()) >= SceneLimits::max_depth)
            p.fail("lists and maps are nested more than " + std::to_string(SceneLimits::max_depth) +
                   " levels deep; no scene needs that many (docs/scene-format.md, Limits)");
        open_.push_back(node);
    }
    if (node.IsSequence()) {
        p.kind = Param::Kind::List;
        for (const auto& item : node) p.items.push_back(convert(item, file, p.line));
    } else if (node.IsMap()) {
        p.kind = Param::Kind::Map;
        for (const auto& kv : node) {
            const YAML::Mark key_mark = kv.first.Mark();
            const int key_line = key_mark.is_null() ? p.line : key_mark.line + 1;
            const std::string where = file + ":" + std::to_string(key_line);
            if (!kv.first.IsScalar()) throw InputError(where, "a map key must be a plain word, not a list or a map");
            const std::string key = kv.first.Scalar();
            if (p.fields.count(key))
                throw InputError(where, "duplicate key " + quote(key) +
                                            "; remove one of the two (the map starts at line " +
                                            std::to_string(p.line) + ")");
            p.fields.emplace(key, convert(kv.second, file, key_line));
        }
    } else {
        p.kind = Param::Kind::Scalar;
        if (node.IsScalar()) p.text = node.Scalar();  // Null / Undefined: an empty scalar
        if (node.IsScalar() && node.Tag() == "!") require_closed_quote(mark, file);  // quoted (or a block scalar)
    }
    if (collection) open_.pop_back();
    return p;
}

// `base: FILE` at the top level: the scene starts from another scene file (the path is
// relative to this file) and replaces or adds the top-level keys it gives. `name` is never
// inherited, so a derived scene is named after its own file. Keys of the base keep their
// own file:line, so an error in inherited input points into the base file.
Param SceneTreeReader::with_base(Param root, const std::string& file, int depth) {
    if (!root.is_map()) return root;
    const auto it = root.fields.find("base");
    if (it == root.fields.end()) return root;
    const Param key = it->second;
    if (!key.is_scalar() || key.text.empty()) key.fail("'base' must be the path of another scene file");
    if (depth >= 8) key.fail("'base' chain is longer than 8 files; is there a cycle?");
    const std::filesystem::path path = std::filesystem::path(file).parent_path() / key.text;
    const std::string base_file = path.string();
    const std::string text = read_scene_file(path, key.location());
    base_files_.push_back(base_file);
    Param base = with_base(convert(parse(text, base_file), base_file), base_file, depth + 1);
    if (!base.is_map()) key.fail("the base scene " + quote(base_file) + " is not a map of keys");
    root.fields.erase("base");
    for (auto& [name, value] : base.fields)
        if (name != "name") root.fields.emplace(name, std::move(value));  // emplace keeps this file's keys
    return root;
}

}  // namespace mbd::detail
