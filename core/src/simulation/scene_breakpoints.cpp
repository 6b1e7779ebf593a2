// The breakpoints of a scene (run_setup.hpp): where its piecewise-constant time functions
// ({type: steps}) jump, so that a run's steps end there and never integrate across a jump.
#include "simulation/run_setup.hpp"

#include <mbd/sdk/number.hpp>

#include <algorithm>

namespace mbd {

namespace {

void collect_breakpoints(const Param& node, std::vector<double>& found) {
    if (node.is_map()) {
        auto type = node.fields.find("type"), table = node.fields.find("table");
        if (type != node.fields.end() && type->second.is_scalar() && type->second.text == "steps" &&
            table != node.fields.end() && table->second.is_list()) {
            const std::vector<Param>& rows = table->second.items;
            for (size_t k = 1; k < rows.size(); ++k) {  // f_0 holds before t_1 too: no jump at t_0
                double t = 0.0;
                if (rows[k].is_list() && !rows[k].items.empty() && rows[k].items[0].is_scalar() &&
                    parse_number(rows[k].items[0].text, t) == NumberText::Valid)
                    found.push_back(t);
            }
        }
        for (const auto& field : node.fields) collect_breakpoints(field.second, found);
    } else if (node.is_list()) {
        for (const Param& item : node.items) collect_breakpoints(item, found);
    }
}

}  // namespace

std::vector<double> scene_breakpoints(const Model& model) {
    std::vector<double> found;
    if (model.document) collect_breakpoints(*model.document, found);
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
}

}  // namespace mbd
