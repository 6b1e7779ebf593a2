// Every JSON output of mbd (`simulate --json`, `statics --json`, `bench --json`) is built as
// one nlohmann::ordered_json document (keys in the order they are set) and printed by
// json_text, so quoting, escaping and number spelling are the library's, never hand-made.
//
// Non-finite numbers: JSON has no NaN or infinity. json_text writes such a value as null and
// lists where it was under the top-level key "non_finite" (JSON pointers, RFC 6901, e.g.
// ["/position_violation"]); the key is absent when every number is finite, so a reader
// tells "not finite" (listed) from "not applicable" (a null the command always writes).
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <string>

namespace mbd {

using Json = nlohmann::ordered_json;

// The document as text: one line (indent < 0) or indented; non-finite numbers as above;
// bytes that are not UTF-8 (a file name) replaced by U+FFFD rather than refused.
std::string json_text(Json document, int indent = -1);

// A vector as a JSON array of numbers.
Json json_array(const Eigen::VectorXd& values);

}  // namespace mbd
