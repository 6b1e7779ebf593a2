// Event-located impacts between collision shapes (collision_impacts.hpp).
#include "collision_impacts.hpp"

#include <algorithm>

namespace mbd::collision {
namespace {

bool has_exact_gap(ShapeKind kind) { return kind == ShapeKind::Sphere || kind == ShapeKind::Plane; }

Vec3 centre(const Shape& s, const SpatialBody& body) { return body.R + body.A * s.position; }

}  // namespace

ImpactPairs::ImpactPairs(const std::vector<Shape>& shapes, const PairFilter& filter) : shapes_(&shapes) {
    for (int i = 0; i < static_cast<int>(shapes.size()); ++i)
        for (int j = i + 1; j < static_cast<int>(shapes.size()); ++j) {
            const ImpactLaw& li = shapes[i].material.impact;
            const ImpactLaw& lj = shapes[j].material.impact;
            if ((!li.given && !lj.given) || !filter.may_touch(i, j)) continue;
            const Shape& asking = li.given ? shapes[i] : shapes[j];
            for (const Shape* s : {&shapes[i], &shapes[j]})
                if (!has_exact_gap(s->kind))
                    throw InputError(asking.where, asking.label + " material: 'impact' (Newton's law at touch-down) "
                                     "is located between spheres and planes only, and it may touch " + s->label +
                                     ": give 'impact' only to spheres and planes, or put the shapes in collision "
                                     "groups that do not touch ('group', 'collides_with')");
            Pair p{i, j, 1.0, 0.0};
            for (const ImpactLaw* law : {&li, &lj})
                if (law->given) {
                    p.restitution = std::min(p.restitution, law->restitution);
                    p.rest_velocity = std::max(p.rest_velocity, law->rest_velocity);
                }
            if (shapes[j].kind == ShapeKind::Plane) std::swap(p.a, p.b);  // the plane first
            pairs_.push_back(p);
        }
}

std::string ImpactPairs::name(int pair) const {
    const Pair& p = pairs_.at(pair);
    return (*shapes_)[p.a].label + " with " + (*shapes_)[p.b].label;
}

ImpactPairs::Gap ImpactPairs::gap(const Pair& p, const BodyStates& bodies) const {
    const Shape& a = (*shapes_)[p.a];
    const Shape& b = (*shapes_)[p.b];
    const SpatialBody& ba = bodies.spatial(a.body);
    const Vec3 Cb = centre(b, bodies.spatial(b.body));
    if (a.kind == ShapeKind::Plane) {
        const Vec3 n = ba.A * a.rotation.col(2);
        return {n.dot(Cb - centre(a, ba)) - b.radius, n, Vec3(Cb - b.radius * n)};
    }
    const Vec3 d = Cb - centre(a, ba);
    const double distance = d.norm();
    // coincident centres give no normal: any direction (the gap is then -r_a - r_b, deep inside)
    const Vec3 n = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitZ();
    const double g = distance - a.radius - b.radius;
    return {g, n, Vec3(centre(a, ba) + (a.radius + 0.5 * g) * n)};
}

void ImpactPairs::values(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> g) const {
    for (int k = 0; k < count(); ++k) g[k] = gap(pairs_[k], bodies).gap;
}

EventImpact ImpactPairs::impact(int pair, const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> G) const {
    const Pair& p = pairs_.at(pair);
    const Gap at = gap(p, bodies);
    G.setZero();
    const int owners[2] = {(*shapes_)[p.a].body, (*shapes_)[p.b].body};
    const double signs[2] = {-1.0, 1.0};
    for (int k = 0; k < 2; ++k) {
        const SpatialBody& body = bodies.spatial(owners[k]);
        G.segment<3>(6 * owners[k]) += signs[k] * at.normal;
        G.segment<3>(6 * owners[k] + 3) += signs[k] * (body.A.transpose() * (at.point - body.R).cross(at.normal));
    }
    EventImpact law;
    law.impact = true;
    law.restitution = p.restitution;
    law.rest_velocity = p.rest_velocity;
    law.holds_resting = true;  // a body's material always has a normal law (only the ground's may be rigid)
    return law;
}

}  // namespace mbd::collision
