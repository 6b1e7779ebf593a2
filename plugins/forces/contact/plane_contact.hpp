// A sphere (planar: a circle) on body j against a plane (planar: a line) fixed to body i
// (or the ground), with the compliant normal law and friction of mbd/sdk/contact.hpp.
//
// Keys: `points: [plane point, sphere centre]` (each in its body's own frame; default the
// mass centres), `normal` (the plane's unit normal in body i's axes, toward the side where
// the sphere is; any length), `radius` r (> 0), and the law's keys (contact.hpp). The plane
// is unbounded: g = n . (C - P0) - r, with C the sphere centre and P0 the plane point; the
// contact point X is the foot of C on the plane.
#pragma once

#include "contact_frames.hpp"

#include <mbd/sdk/contact.hpp>

#include <string>

namespace mbd::contact {

class PlaneContact final : public ContactForce<PlaneContact> {
public:
    PlaneContact(const ForceSpec& spec, Dimension accepted, const std::string& other)
        : ContactForce(spec, accepted, other) {
        const auto u = contact_points(spec, "plane point, sphere centre");
        plane_point_ = u[0];
        centre_ = u[1];
        const std::string what = "the unit normal of the plane in body i's axes, e.g. [0, 0, 1]";
        if (spec.dimension == Dimension::Planar)
            normal_bar_ << unit_direction<2>(spec, "normal", what), 0.0;
        else
            normal_bar_ = unit_direction<3>(spec, "normal", what);
        radius_ = positive_length(spec, "radius", "the sphere's radius");
        refuse_deep_start(spec, radius_, spec.dimension == Dimension::Planar ? "the circle's radius" : "the sphere's radius");
    }

    template <class S>
    ContactGeometry<S, 2> geometry(const force_support::PlanarStates<S>& s) const {
        return sphere_on_plane<S, 2>(s[0].point(plane_point_.head<2>()), s[0].A * normal_bar_.head<2>().cast<S>(),
                                     s[1].point(centre_.head<2>()), radius_);
    }
    template <class S>
    ContactGeometry<S, 3> geometry(const force_support::SpatialStates<S>& s) const {
        return sphere_on_plane<S, 3>(s[0].point(plane_point_), s[0].A * normal_bar_.cast<S>(), s[1].point(centre_),
                                     radius_);
    }

private:
    Vec3 plane_point_, centre_, normal_bar_;
    double radius_ = 0.0;
};

}  // namespace mbd::contact
