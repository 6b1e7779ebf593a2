// The frames of a contact element: its two points, one per body in that body's own frame
// (the scene's `points`; default the mass centres). A world `point` or `axis` (the
// joint-style frame of other two-body forces) is refused: it would put both markers at one
// world point.
#pragma once

#include <mbd/sdk/force_support.hpp>

#include <array>

namespace mbd::contact {

inline std::array<Vec3, 2> contact_points(const ForceSpec& spec, const char* what) {
    for (const char* key : {"point", "axis"})
        if (spec.params.has(key))
            force_support::fail(spec, std::string("a contact takes 'points: [") + what +
                                          "]', each in its body's own frame, not a world '" + key + "'",
                                &spec.params.at(key));
    std::array<Vec3, 2> u{force_support::marker_or_centre(spec, 0).u_bar, force_support::marker_or_centre(spec, 1).u_bar};
    if (spec.dimension == Dimension::Planar) u[0].z() = u[1].z() = 0.0;
    return u;
}

}  // namespace mbd::contact
