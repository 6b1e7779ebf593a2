// Parameters of a scene element, as a plugin sees them: a small tree of
// scalars, strings, lists and maps, each node remembering its source line so
// that every error can point at file:line. The core converts YAML into this
// tree, so plugins never depend on the YAML library.
#pragma once

#include <mbd/sdk/number.hpp>

#include <Eigen/Core>

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

// Types that cross the plugin boundary keep default visibility so that their
// type information (exceptions, vtables) is shared between host and plugins.
#define MBD_SDK_API __attribute__((visibility("default")))

namespace mbd {

// Thrown for any input the user must fix. `where` is "file:line" or an
// element name; the CLI prints "error: <where>: <message>".
class MBD_SDK_API InputError : public std::runtime_error {
public:
    InputError(std::string where, const std::string& message)
        : std::runtime_error(where.empty() ? message : where + ": " + message),
          where_(std::move(where)), message_(message) {}
    const std::string& where() const { return where_; }
    const std::string& message() const { return message_; }

private:
    std::string where_;
    std::string message_;
};

class Param {
public:
    enum class Kind { Scalar, List, Map };

    Kind kind = Kind::Scalar;
    std::string text;                 // scalar text as written
    std::vector<Param> items;         // list items
    std::map<std::string, Param> fields;
    std::string file;
    int line = 0;

    std::string location() const {
        if (file.empty()) return line > 0 ? "line " + std::to_string(line) : std::string();
        return line > 0 ? file + ":" + std::to_string(line) : file;
    }

    bool is_scalar() const { return kind == Kind::Scalar; }
    bool is_list() const { return kind == Kind::List; }
    bool is_map() const { return kind == Kind::Map; }

    // The number under `key` (docs/scene-format.md, Conventions): finite, in the range of a
    // double; refused at this node's file:line naming the key, after `owner` (the element).
    double as_number(const std::string& key, const std::string& owner = std::string()) const {
        const std::string prefix = owner.empty() ? std::string() : owner + ": ";
        if (kind != Kind::Scalar) fail(prefix + "'" + key + "' must be a number, not a list or a map");
        double value = 0.0;
        const NumberText read = parse_number(text, value);
        if (read != NumberText::Valid) fail(prefix + number_problem(read, key, text));
        return value;
    }

    // A whole number in [lo, hi] (counts, iteration limits), refused like as_number.
    long long as_integer(const std::string& key, long long lo, long long hi,
                         const std::string& owner = std::string()) const {
        const double value = as_number(key, owner);
        const std::string prefix = owner.empty() ? std::string() : owner + ": ";
        if (value != std::floor(value)) fail(prefix + "'" + key + "' must be a whole number, got '" + text + "'");
        if (!(value >= static_cast<double>(lo) && value <= static_cast<double>(hi)))
            fail(prefix + "'" + key + "' must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                 ", got '" + text + "'");
        return static_cast<long long>(value);
    }

    Eigen::VectorXd as_vector(const std::string& what, int expected_size = -1,
                              const std::string& owner = std::string()) const {
        const std::string prefix = owner.empty() ? std::string() : owner + ": ";
        if (kind != Kind::List) fail(prefix + "'" + what + "' must be a list of numbers");
        if (expected_size >= 0 && static_cast<int>(items.size()) != expected_size)
            fail(prefix + "'" + what + "' must have " + std::to_string(expected_size) + " numbers, got " +
                 std::to_string(items.size()));
        Eigen::VectorXd v(items.size());
        for (size_t k = 0; k < items.size(); ++k) v[k] = items[k].as_number(what, owner);
        return v;
    }

    [[noreturn]] void fail(const std::string& message) const { throw InputError(location(), message); }
};

// Keyed access to a map node that records which keys were asked for, so that
// the core can reject keys nobody read ("did you mean ...?").
class Params {
public:
    Params() = default;
    Params(std::string owner, const Param* node) : owner_(std::move(owner)), node_(node) {}

    const std::string& owner() const { return owner_; }
    std::string location() const { return node_ ? node_->location() : std::string(); }

    bool has(const std::string& key) const {
        asked_->insert(key);
        return node_ && node_->is_map() && node_->fields.count(key) > 0;
    }
    const Param& at(const std::string& key) const {
        if (!has(key)) fail("missing key '" + key + "'");
        return node_->fields.at(key);
    }
    double number(const std::string& key) const { return at(key).as_number(key, owner_); }
    double number(const std::string& key, double fallback) const {
        return has(key) ? number(key) : fallback;
    }
    double positive(const std::string& key) const {
        double v = number(key);
        if (!(v > 0)) at(key).fail("'" + key + "' must be positive, got " + at(key).text);
        return v;
    }
    double non_negative(const std::string& key, double fallback) const {
        double v = number(key, fallback);
        if (!(v >= 0)) at(key).fail("'" + key + "' must not be negative");
        return v;
    }
    // A whole number in [lo, hi] (iteration limits, sizes).
    long long integer(const std::string& key, long long lo, long long hi) const {
        return at(key).as_integer(key, lo, hi, owner_);
    }
    std::string string(const std::string& key) const {
        const Param& p = at(key);
        if (!p.is_scalar()) p.fail("'" + key + "' must be a single word");
        return p.text;
    }
    std::string string(const std::string& key, const std::string& fallback) const {
        return has(key) ? string(key) : fallback;
    }
    Eigen::VectorXd vector(const std::string& key, int expected_size = -1) const {
        return at(key).as_vector(key, expected_size, owner_);
    }
    Params child(const std::string& key) const {
        const Param& p = at(key);
        if (!p.is_map()) p.fail("'" + key + "' must be a map of keys");
        return Params(owner_ + "." + key, &p);
    }

    // Keys present in the node that nobody asked for.
    std::vector<std::string> unread_keys() const {
        std::vector<std::string> out;
        if (!node_ || !node_->is_map()) return out;
        for (const auto& kv : node_->fields)
            if (!asked_->count(kv.first)) out.push_back(kv.first);
        return out;
    }
    const std::set<std::string>& asked_keys() const { return *asked_; }
    void mark_read(const std::string& key) const { asked_->insert(key); }
    const Param* node() const { return node_; }

    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(location(), owner_ + ": " + message);
    }

private:
    std::string owner_;
    const Param* node_ = nullptr;
    std::shared_ptr<std::set<std::string>> asked_ = std::make_shared<std::set<std::string>>();
};

}  // namespace mbd
