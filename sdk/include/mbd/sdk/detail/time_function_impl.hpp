// Inline implementation of make_time_function (declared in time_function.hpp).
//
// Every function returns f, df/dt and d2f/dt2 in closed form (no finite
// differences). Scene forms and the keys each type reads:
//   constant    value
//   linear      initial (default 0), rate                    f = initial + rate t
//   polynomial  coefficients: [c0, c1, ...] (at least one)     f = sum c_k t^k
//   harmonic    amplitude, frequency (rad/s), phase (default 0), offset (default 0)
//                                                             f = offset + amplitude sin(frequency t + phase)
//   smooth_step t0 (default 0), t1 (> t0), from (default 0), to
//               quintic h(s) = 10 s^3 - 15 s^4 + 6 s^5, s = (t - t0)/(t1 - t0): f = from + (to - from) h,
//               zero rate and acceleration at t0 and t1, constant outside [t0, t1]
//   spline      table: [[t0, f0], [t1, f1], ...] (t strictly increasing, at least 2 points)
//               natural cubic spline (f'' = 0 at both ends); outside the table it continues
//               linearly with the end slope (f'' = 0), so f, f' and f'' are continuous everywhere
//   steps       table: [[t0, f0], [t1, f1], ...] (t strictly increasing, at least 1 point):
//               piecewise constant, f = f_k on [t_k, t_{k+1}), f0 before t0 (a zero-order
//               hold, as recorded inputs are replayed); f' = f'' = 0
//   input       name: the value of the input NAME that the program stepping the simulation
//               sets (current_input_values, time_function.hpp), held: f' = f'' = 0
// A bare number is a constant. Unknown keys are errors (with a "did you mean" hint).
#pragma once

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/suggest.hpp>
#include <mbd/sdk/time_function.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mbd {
namespace detail {

inline std::string tf_join(const std::vector<std::string>& words) {
    std::string out;
    for (size_t k = 0; k < words.size(); ++k) out += (k ? ", " : "") + words[k];
    return out;
}

inline const std::vector<std::string>& tf_known_types() {
    static const std::vector<std::string> types = {"constant", "linear",     "polynomial",
                                                   "harmonic", "smooth_step", "spline", "steps", "input"};
    return types;
}

// Reads the fields of one time-function map, with messages that name the element.
class TfReader {
public:
    TfReader(const Param& node, std::string what, std::string type)
        : node_(node), what_(std::move(what)), type_(std::move(type)) {}

    [[noreturn]] void fail(const Param& where, const std::string& message) const {
        throw InputError(where.location().empty() ? node_.location() : where.location(),
                         what_ + ": time function '" + type_ + "': " + message);
    }
    [[noreturn]] void fail(const std::string& message) const { fail(node_, message); }

    bool has(const std::string& key) const { return node_.fields.count(key) > 0; }

    double number(const std::string& key) const {
        auto it = node_.fields.find(key);
        if (it == node_.fields.end()) fail("missing key '" + key + "'");
        return to_number(it->second, key);
    }
    double number(const std::string& key, double fallback) const {
        return has(key) ? number(key) : fallback;
    }
    double to_number(const Param& p, const std::string& key) const {
        return p.as_number(key, what_ + ": time function '" + type_ + "'");
    }
    const Param& list(const std::string& key) const {
        auto it = node_.fields.find(key);
        if (it == node_.fields.end()) fail("missing key '" + key + "'");
        if (!it->second.is_list()) fail(it->second, "'" + key + "' must be a list");
        return it->second;
    }

    // Every key of the map must be one the type uses.
    void check_keys(const std::vector<std::string>& allowed) const {
        for (const auto& kv : node_.fields) {
            if (kv.first == "type") continue;
            if (std::find(allowed.begin(), allowed.end(), kv.first) != allowed.end()) continue;
            const std::string best = nearest_name(kv.first, allowed);
            std::string msg = "unknown key '" + kv.first + "'";
            if (!best.empty()) msg += " (did you mean '" + best + "'?)";
            msg += "; the keys of a " + type_ + " are: type, " + tf_join(allowed);
            fail(kv.second, msg);
        }
    }

private:
    const Param& node_;
    std::string what_;
    std::string type_;
};

class TfConstant final : public TimeFunction {
public:
    explicit TfConstant(double c) : c_(c) {}
    TimeValue evaluate(double) const override { return {c_, 0.0, 0.0}; }

private:
    double c_;
};

class TfPolynomial final : public TimeFunction {
public:
    explicit TfPolynomial(std::vector<double> c) : c_(std::move(c)) {}
    TimeValue evaluate(double t) const override {
        // Horner for f, f', f'' together.
        double f = 0, df = 0, ddf = 0;
        for (size_t k = c_.size(); k-- > 0;) {
            ddf = ddf * t + 2.0 * df;
            df = df * t + f;
            f = f * t + c_[k];
        }
        return {f, df, ddf};
    }

private:
    std::vector<double> c_;
};

class TfHarmonic final : public TimeFunction {
public:
    TfHarmonic(double amplitude, double frequency, double phase, double offset)
        : a_(amplitude), w_(frequency), p_(phase), c_(offset) {}
    TimeValue evaluate(double t) const override {
        const double s = std::sin(w_ * t + p_), co = std::cos(w_ * t + p_);
        return {c_ + a_ * s, a_ * w_ * co, -a_ * w_ * w_ * s};
    }

private:
    double a_, w_, p_, c_;
};

class TfSmoothStep final : public TimeFunction {
public:
    TfSmoothStep(double t0, double t1, double from, double to) : t0_(t0), t1_(t1), f0_(from), f1_(to) {}
    TimeValue evaluate(double t) const override {
        if (t <= t0_) return {f0_, 0.0, 0.0};
        if (t >= t1_) return {f1_, 0.0, 0.0};
        const double T = t1_ - t0_, s = (t - t0_) / T, d = f1_ - f0_;
        const double h = s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
        const double h1 = s * s * (30.0 + s * (-60.0 + 30.0 * s));
        const double h2 = s * (60.0 + s * (-180.0 + 120.0 * s));
        return {f0_ + d * h, d * h1 / T, d * h2 / (T * T)};
    }

private:
    double t0_, t1_, f0_, f1_;
};

// Piecewise constant: f_k on [t_k, t_{k+1}).
class TfSteps final : public TimeFunction {
public:
    TfSteps(std::vector<double> t, std::vector<double> f) : t_(std::move(t)), f_(std::move(f)) {}
    TimeValue evaluate(double t) const override {
        const size_t after = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
        return {f_[after == 0 ? 0 : after - 1], 0.0, 0.0};
    }

private:
    std::vector<double> t_, f_;
};

// A value the program sets (current_input_values), held between its changes.
class TfInput final : public TimeFunction {
public:
    TfInput(std::string name, std::string what) : name_(std::move(name)), what_(std::move(what)) {}
    TimeValue evaluate(double /*t*/) const override {
        const InputValues* table = current_input_values();
        if (!table)
            throw InputError(what_, "the input '" + name_ +
                                        "' has a value only while a Simulator steps the scene (set_input, "
                                        "docs/embedding.md); a whole run (simulate) has no inputs: give it a "
                                        "time function instead");
        return {table->value(name_), 0.0, 0.0};
    }

private:
    std::string name_, what_;
};

// Natural cubic spline in second-derivative (moment) form.
class TfSpline final : public TimeFunction {
public:
    TfSpline(std::vector<double> t, std::vector<double> f) : t_(std::move(t)), f_(std::move(f)) {
        const size_t n = t_.size();
        m_.assign(n, 0.0);
        if (n > 2) {
            // Tridiagonal system for the interior moments (Thomas algorithm), m_0 = m_{n-1} = 0.
            std::vector<double> a(n, 0.0), b(n, 0.0), c(n, 0.0), r(n, 0.0);
            for (size_t i = 1; i + 1 < n; ++i) {
                const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
                a[i] = h0 / 6.0;
                b[i] = (h0 + h1) / 3.0;
                c[i] = h1 / 6.0;
                r[i] = (f_[i + 1] - f_[i]) / h1 - (f_[i] - f_[i - 1]) / h0;
            }
            for (size_t i = 2; i + 1 < n; ++i) {
                const double w = a[i] / b[i - 1];
                b[i] -= w * c[i - 1];
                r[i] -= w * r[i - 1];
            }
            for (size_t i = n - 2; i >= 1; --i) {
                m_[i] = (r[i] - c[i] * m_[i + 1]) / b[i];
                if (i == 1) break;
            }
        }
    }
    TimeValue evaluate(double t) const override {
        const size_t n = t_.size();
        if (t <= t_.front()) {
            const double s = slope(0, true);
            return {f_.front() + s * (t - t_.front()), s, 0.0};
        }
        if (t >= t_.back()) {
            const double s = slope(n - 2, false);
            return {f_.back() + s * (t - t_.back()), s, 0.0};
        }
        const size_t i = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
        return segment(i, t);
    }

private:
    TimeValue segment(size_t i, double t) const {
        const double h = t_[i + 1] - t_[i];
        const double A = (t_[i + 1] - t) / h, B = (t - t_[i]) / h;
        const double f = A * f_[i] + B * f_[i + 1] +
                         ((A * A * A - A) * m_[i] + (B * B * B - B) * m_[i + 1]) * h * h / 6.0;
        const double df = (f_[i + 1] - f_[i]) / h - (3 * A * A - 1) * h / 6.0 * m_[i] +
                          (3 * B * B - 1) * h / 6.0 * m_[i + 1];
        const double ddf = A * m_[i] + B * m_[i + 1];
        return {f, df, ddf};
    }
    // Slope at the left end of segment i (left = true) or at its right end.
    double slope(size_t i, bool left) const { return segment(i, left ? t_[i] : t_[i + 1]).df; }

    std::vector<double> t_, f_, m_;
};

// spline and steps: a table [[t0, f0], [t1, f1], ...] with strictly increasing times.
inline std::shared_ptr<const TimeFunction> tf_from_table(const TfReader& in, const std::string& type) {
    in.check_keys({"table"});
    const Param& table = in.list("table");
    const size_t fewest = type == "spline" ? 2 : 1;
    if (table.items.size() < fewest)
        in.fail(table, "'table' needs at least " + std::to_string(fewest) +
                           (fewest == 1 ? " point [[t0, f0], ...]" : " points [[t0, f0], [t1, f1], ...]") +
                           ", got " + std::to_string(table.items.size()));
    std::vector<double> ts, fs;
    for (size_t k = 0; k < table.items.size(); ++k) {
        const Param& row = table.items[k];
        if (!row.is_list() || row.items.size() != 2)
            in.fail(row, "'table' row " + std::to_string(k + 1) + " must be a pair [t, f]");
        const double t = in.to_number(row.items[0], "table"), f = in.to_number(row.items[1], "table");
        if (!ts.empty() && !(t > ts.back()))
            in.fail(row, "'table' times must be strictly increasing: row " + std::to_string(k + 1) + " has t = " +
                             row.items[0].text + " after t = " + std::to_string(ts.back()));
        ts.push_back(t);
        fs.push_back(f);
    }
    if (type == "steps") return std::make_shared<TfSteps>(std::move(ts), std::move(fs));
    return std::make_shared<TfSpline>(std::move(ts), std::move(fs));
}

// The function of a bare number (a constant), or the error for a scalar that is not one.
inline std::shared_ptr<const TimeFunction> tf_from_scalar(const Param& node, const std::string& what,
                                                          const std::string& known) {
    double value = 0.0;
    const NumberText read = parse_number(node.text, value);
    if (read == NumberText::Valid) return std::make_shared<TfConstant>(value);
    if (read != NumberText::NotANumber)
        throw InputError(node.location(), what + ": a constant time function " + number_problem(read, "value", node.text));
    throw InputError(node.location(),
                     what + ": a time function is a number or a map with 'type' (" + known + "), got '" + node.text + "'");
}

}  // namespace detail

inline std::shared_ptr<const TimeFunction> make_time_function(const Param& node, const std::string& what) {
    using namespace detail;
    const std::string known = tf_join(tf_known_types());
    if (node.is_scalar()) return tf_from_scalar(node, what, known);
    if (!node.is_map())
        throw InputError(node.location(), what + ": a time function is a number or a map with 'type' (" +
                                              known + "), not a list");
    auto type_it = node.fields.find("type");
    if (type_it == node.fields.end())
        throw InputError(node.location(), what + ": time function needs a 'type' (one of " + known + ")");
    if (!type_it->second.is_scalar())
        throw InputError(type_it->second.location().empty() ? node.location() : type_it->second.location(),
                         what + ": time function 'type' must be one of " + known);
    const std::string type = type_it->second.text;
    const TfReader in(node, what, type);

    if (type == "input") {
        in.check_keys({"name"});
        auto it = node.fields.find("name");
        if (it == node.fields.end() || !it->second.is_scalar() || it->second.text.empty())
            in.fail("needs a 'name' (the name the program sets it by: set_input(name, value))");
        return std::make_shared<TfInput>(it->second.text, what);
    }
    if (type == "constant") {
        in.check_keys({"value"});
        return std::make_shared<TfConstant>(in.number("value"));
    }
    if (type == "linear") {
        in.check_keys({"initial", "rate"});
        return std::make_shared<TfPolynomial>(std::vector<double>{in.number("initial", 0.0), in.number("rate")});
    }
    if (type == "polynomial") {
        in.check_keys({"coefficients"});
        const Param& list = in.list("coefficients");
        if (list.items.empty()) in.fail(list, "'coefficients' needs at least one number [c0, c1, ...]");
        std::vector<double> c;
        for (const Param& item : list.items) c.push_back(in.to_number(item, "coefficients"));
        return std::make_shared<TfPolynomial>(std::move(c));
    }
    if (type == "harmonic") {
        in.check_keys({"amplitude", "frequency", "phase", "offset"});
        return std::make_shared<TfHarmonic>(in.number("amplitude"), in.number("frequency"),
                                            in.number("phase", 0.0), in.number("offset", 0.0));
    }
    if (type == "smooth_step") {
        in.check_keys({"t0", "t1", "from", "to"});
        const double t0 = in.number("t0", 0.0), t1 = in.number("t1");
        if (!(t1 > t0))
            in.fail("t1 (" + std::to_string(t1) + ") must be greater than t0 (" + std::to_string(t0) +
                    "): the step runs from t0 to t1");
        return std::make_shared<TfSmoothStep>(t0, t1, in.number("from", 0.0), in.number("to"));
    }
    if (type == "spline" || type == "steps") return tf_from_table(in, type);
    throw InputError(type_it->second.location().empty() ? node.location() : type_it->second.location(),
                     what + ": unknown time function type '" + type + "'; known types: " + known);
}

}  // namespace mbd
