// JSON outputs (see json_output.hpp).
#include <mbd/app/json_output.hpp>

#include <cmath>

namespace mbd {

namespace {

// A key as a JSON-pointer token (RFC 6901: '~' -> "~0", '/' -> "~1").
std::string pointer_token(const std::string& key) {
    std::string out;
    for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    return out;
}

// Replaces every non-finite number under `node` by null and records its pointer in `found`.
void null_non_finite(Json& node, const std::string& pointer, Json& found) {
    if (node.is_number_float()) {
        if (!std::isfinite(node.get<double>())) {
            found.push_back(pointer);
            node = nullptr;
        }
    } else if (node.is_object()) {
        for (auto& item : node.items()) null_non_finite(item.value(), pointer + "/" + pointer_token(item.key()), found);
    } else if (node.is_array()) {
        for (std::size_t k = 0; k < node.size(); ++k) null_non_finite(node[k], pointer + "/" + std::to_string(k), found);
    }
}

}  // namespace

std::string json_text(Json document, int indent) {
    Json found = Json::array();
    null_non_finite(document, "", found);
    if (!found.empty() && document.is_object()) document["non_finite"] = found;
    return document.dump(indent, ' ', false, Json::error_handler_t::replace);
}

Json json_array(const Eigen::VectorXd& values) {
    Json out = Json::array();
    for (Eigen::Index k = 0; k < values.size(); ++k) out.push_back(values[k]);
    return out;
}

}  // namespace mbd
