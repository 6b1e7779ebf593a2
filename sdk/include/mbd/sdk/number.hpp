// The one reader of numbers written in a scene (core, plugins and the SDK helpers all
// go through Param::as_number, which uses it). The whole text must be a decimal number,
// optionally signed and with an exponent, within the range of a double. NaN and
// infinity are refused in every spelling ("nan", ".inf", "-Infinity", ...): no scene
// value means them, and one that slipped through would poison a run silently or
// overflow a conversion to an integer.
#pragma once

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

namespace mbd {

enum class NumberText { Valid, NotANumber, NotFinite, OutOfRange };

// Parses `text` into `value` (untouched unless Valid). Locale-independent.
inline NumberText parse_number(const std::string& text, double& value) {
    const char* first = text.data();
    const char* last = first + text.size();
    const bool plus = first != last && *first == '+';  // YAML allows an explicit '+', from_chars does not
    if (plus) ++first;
    double parsed = 0.0;
    const auto [end, error] = std::from_chars(first, last, parsed, std::chars_format::general);
    const bool signed_twice = plus && first != last && (*first == '-' || *first == '+');
    if (error == std::errc::result_out_of_range && end == last && !signed_twice) return NumberText::OutOfRange;
    if (error != std::errc() || end != last || first == last || signed_twice) {
        // name the non-finite spellings (YAML's .inf and .nan among them) for what they are
        std::string word;
        for (const char* c = text.data(); c != last; ++c)
            if (*c != '+' && *c != '-' && *c != '.') word += static_cast<char>(std::tolower(static_cast<unsigned char>(*c)));
        if (word == "inf" || word == "infinity" || word == "nan") return NumberText::NotFinite;
        return NumberText::NotANumber;
    }
    if (!std::isfinite(parsed)) return NumberText::NotFinite;
    value = parsed;
    return NumberText::Valid;
}

// Why `text` under `key` was refused, e.g. "'mass' must be a finite number, got 'inf'".
inline std::string number_problem(NumberText problem, const std::string& key, const std::string& text) {
    const std::string got = ", got '" + text + "'";
    switch (problem) {
        case NumberText::NotFinite:
            return "'" + key + "' must be a finite number" + got;
        case NumberText::OutOfRange:
            return "'" + key + "' is out of the range of a double (magnitudes from about 2.2e-308 to 1.8e308)" + got;
        default:
            return "'" + key + "' must be a number" + got;
    }
}

}  // namespace mbd
