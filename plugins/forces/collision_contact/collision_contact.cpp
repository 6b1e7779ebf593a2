// The force element 'collision_contact': compliant contact between any collision shapes of a
// spatial scene, found by FCL (collision_world.hpp) and loaded by the laws of the two-body
// contact elements (mbd/sdk/contact.hpp: Hunt-Crossley normal force, regularized Coulomb
// friction). The core adds one such element over every body with `collision:` shapes
// (core/src/scene/scene_collision.cpp); it is never written under `forces:`.
//
// Each contact's force F = contact_load(...) acts on shape j's body at the contact point and -F
// on shape i's, so the element conserves the momentum and angular momentum of the bodies it
// touches. It declares no events: the set of contacts changes between evaluations, and the
// force's onset is smooth enough (F_n = k delta^n with n > 1 has a continuous first derivative
// at delta = 0) for the adaptive integrators to find their steps. The exception are the pairs
// whose material asks for impacts (`impact:`): each is an event, its gap, at whose closing the
// core applies Newton's impulse (collision_impacts.hpp). It reports its contacts
// (mbd/sdk/contact_report.hpp) for `mbd simulate --contacts` and the viewer.
#include "collision_impacts.hpp"
#include "collision_world.hpp"

#include <mbd/sdk/contact_report.hpp>
#include <mbd/sdk/force_couplings.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <algorithm>
#include <map>
#include <mutex>

namespace mbd::collision {
namespace {

force_support::SpatialT<double> kinematics(const SpatialBody& b) { return {b.R, b.Rdot, b.omega_bar, b.A}; }

class CollisionContact final : public Force, public ForceCouplings, public ContactReporter {
public:
    explicit CollisionContact(const ForceSpec& spec) {
        if (spec.dimension != Dimension::Spatial)
            force_support::fail(spec, "collision shapes are spatial only; in a planar scene use circle_line and "
                                      "circle_circle");
        const Param& lists = spec.params.at("shapes");
        for (size_t k = 0; k < lists.items.size(); ++k) {
            const Param& entry = lists.items[k];
            const BodyInfo& body = spec.bodies[k];
            if (body.ground) ground_body_ = static_cast<int>(k);
            const bool massless = !body.ground && (body.mass <= 0.0 || body.inertia.diagonal().minCoeff() <= 0.0);
            std::vector<Shape> read =
                read_shapes(entry.fields.at("collision"), body.name, static_cast<int>(k), body.ground, massless);
            shapes_.insert(shapes_.end(), read.begin(), read.end());
        }
        check_exponents();
        std::set<std::pair<int, int>> joined;
        for (const Param& pair : spec.params.at("joined").items) {
            const int a = static_cast<int>(pair.items[0].as_integer("joined", 0, 1 << 30));
            const int b = static_cast<int>(pair.items[1].as_integer("joined", 0, 1 << 30));
            joined.insert({std::min(a, b), std::max(a, b)});
        }
        filter_ = PairFilter(shapes_, std::move(joined));
        impacts_ = ImpactPairs(shapes_, filter_);
    }

    // --- events: the pairs with Newton's impact law (collision_impacts.hpp)
    int event_count() const override { return impacts_.count(); }
    std::string event_name(int event) const override { return impacts_.name(event); }
    void event_values(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> g) const override {
        impacts_.values(bodies, g);
    }
    EventImpact event_impact(int event, const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> G) const override {
        return impacts_.impact(event, bodies, G);
    }

    void evaluate(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Borrowed world(*this);
        for (const Contact& c : world->detect(bodies)) {
            const int bi = shapes_[c.shape_i].body, bj = shapes_[c.shape_j].body;
            add_contact_load(bodies, c, Q.segment<6>(6 * bi), Q.segment<6>(6 * bj));
        }
    }

    // --- sparse Jacobians (mbd/sdk/force_couplings.hpp): one coupling per pair of shapes in
    // contact, whose force is that of the pair's contacts
    void couplings(const BodyStates& bodies, std::vector<ForceCoupling>& out) const override {
        out.clear();
        Borrowed world(*this);
        // the narrow phase gives each pair's contacts together, each pair once (collision_world.cpp)
        for (const Contact& c : world->detect(bodies))
            if (out.empty() || out.back().item_i != c.shape_i || out.back().item_j != c.shape_j)
                out.push_back({shapes_[c.shape_i].body, shapes_[c.shape_j].body, c.shape_i, c.shape_j});
    }

    void coupling_force(const BodyStates& bodies, const ForceCoupling& pair, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Borrowed world(*this);
        for (const Contact& c : world->detect_pair(pair.item_i, pair.item_j, bodies))
            add_contact_load(bodies, c, Q.segment<6>(0), Q.segment<6>(6));
    }

    // The same contacts and loads as evaluate(), each split into its normal and friction parts, with
    // the rolling resistance's torque.
    std::vector<ContactReport> contacts(const BodyStates& bodies) const override {
        Borrowed world(*this);
        std::vector<ContactReport> reports;
        for (const Contact& c : world->detect(bodies)) {
            const Load l = load(c, bodies);
            const Vec3& F = l.force;
            ContactReport r;
            r.body_i = shapes_[c.shape_i].body;
            r.body_j = shapes_[c.shape_j].body;
            r.point = c.point;
            r.normal = c.normal;
            r.depth = c.depth;
            r.normal_force = F.dot(c.normal);
            r.friction_force = F - r.normal_force * c.normal;
            r.rolling_torque = l.torque;
            reports.push_back(r);
        }
        return reports;
    }

    // The elastic energy stored in the contacts (k delta^(n+1) / (n + 1) each).
    double potential_energy(const BodyStates& bodies) const override {
        Borrowed world(*this);
        double V = 0.0;
        for (const Contact& c : world->detect(bodies))
            V += pair_law(shapes_[c.shape_i].material, curvature_radius(shapes_[c.shape_i]),
                          shapes_[c.shape_j].material, curvature_radius(shapes_[c.shape_j]))
                     .normal.energy(c.depth);
        return V;
    }

    // Undamped and frictionless, the contacts' forces derive from their elastic energy (exactly
    // where the gap rate is the depth's derivative: spheres, planes; collision_world.hpp).
    bool is_conservative() const override {
        for (const Shape& s : shapes_)
            if ((!s.material.rigid && s.material.normal.damping != 0.0) || s.material.friction.mu_static != 0.0 ||
                s.material.rolling_resistance != 0.0)
                return false;
        return true;
    }

    // For the automatic choice (Force::compliant_laws): each body's stiffest law against the
    // ground's shapes, or, with none, against its own shapes (two bodies of one kind).
    std::vector<CompliantLaw> compliant_laws() const override {
        std::vector<const Shape*> ground;
        for (const Shape& s : shapes_)
            if (ground_body_ >= 0 && s.body == ground_body_) ground.push_back(&s);
        std::map<int, CompliantLaw> stiffest;  // by body
        for (const Shape& s : shapes_) {
            if (s.body == ground_body_) continue;
            std::vector<const Shape*> partners = ground;
            if (partners.empty()) partners.push_back(&s);
            for (const Shape* p : partners) {
                const PairLaw law = pair_law(s.material, curvature_radius(s), p->material, curvature_radius(*p));
                const double v = std::max(s.material.normal.impact_velocity, p->material.normal.impact_velocity);
                CompliantLaw& best = stiffest.try_emplace(s.body).first->second;
                if (law.normal.stiffness > best.stiffness)
                    best = {law.normal.stiffness, law.normal.exponent, v, p->body, s.body};
            }
        }
        std::vector<CompliantLaw> laws;
        for (const auto& entry : stiffest)
            if (entry.second.stiffness > 0.0) laws.push_back(entry.second);
        return laws;
    }

private:
    // One contact's load on its two bodies: the force F of load() on shape j's body at the contact
    // point and the rolling resistance's torque (moments in body axes) into Q_j, their opposites into Q_i.
    void add_contact_load(const BodyStates& bodies, const Contact& c, Eigen::Ref<Eigen::VectorXd> Q_i,
                          Eigen::Ref<Eigen::VectorXd> Q_j) const {
        const int i = shapes_[c.shape_i].body, j = shapes_[c.shape_j].body;
        const Load l = load(c, bodies);
        contact::add_point_force(kinematics(bodies.spatial(j)), c.point, l.force, Q_j);
        contact::add_point_force(kinematics(bodies.spatial(i)), c.point, Vec3(-l.force), Q_i);
        if (l.torque.isZero(0.0)) return;  // no rolling resistance
        Q_j.segment<3>(3) += bodies.spatial(j).A.transpose() * l.torque;
        Q_i.segment<3>(3) -= bodies.spatial(i).A.transpose() * l.torque;
    }

    // The force of contact c on shape j's body at the contact point (contact_load: the normal law
    // and friction) and the rolling resistance's torque on it (world); their opposites act on
    // shape i's.
    struct Load {
        Vec3 force, torque;
    };
    Load load(const Contact& c, const BodyStates& bodies) const {
        const Shape& si = shapes_[c.shape_i];
        const Shape& sj = shapes_[c.shape_j];
        const PairLaw law = pair_law(si.material, curvature_radius(si), sj.material, curvature_radius(sj));
        const auto bi = kinematics(bodies.spatial(si.body));
        const auto bj = kinematics(bodies.spatial(sj.body));
        const contact::ContactGeometry<double, 3> g{c.normal, c.point, -c.depth, true};
        const Vec3 v_rel = contact::material_velocity(bj, c.point) - contact::material_velocity(bi, c.point);
        const Vec3 F = contact::contact_load(law.normal, law.friction, g, v_rel);
        const Vec3 w_rel = bj.omega() - bi.omega();
        return {F, rolling_torque(law, c.normal, F.dot(c.normal), w_rel)};
    }

    // A World from the pool for one evaluation, returned when done: threads evaluating the same
    // Model each get their own, and after the first evaluations none is allocated.
    class Borrowed {
    public:
        explicit Borrowed(const CollisionContact& owner) : owner_(owner) {
            std::lock_guard<std::mutex> lock(owner_.pool_mutex_);
            if (owner_.pool_.empty()) {
                world_ = std::make_unique<World>(owner_.shapes_, owner_.filter_);
            } else {
                world_ = std::move(owner_.pool_.back());
                owner_.pool_.pop_back();
            }
        }
        ~Borrowed() {
            std::lock_guard<std::mutex> lock(owner_.pool_mutex_);
            owner_.pool_.push_back(std::move(world_));
        }
        World* operator->() { return world_.get(); }

    private:
        const CollisionContact& owner_;
        std::unique_ptr<World> world_;
    };

    // The series law of two compliant materials needs one exponent (collision_material.hpp).
    void check_exponents() const {
        const Shape* first = nullptr;
        for (const Shape& s : shapes_) {
            if (s.material.rigid) continue;
            if (!first) first = &s;
            else if (s.material.normal.exponent != first->material.normal.exponent)
                throw InputError(s.where, s.label + ": its material's exponent " +
                                         format_number(s.material.normal.exponent) + " differs from " + first->label +
                                         "'s " + format_number(first->material.normal.exponent) +
                                         ": the contact law of two materials in series needs one exponent n; give "
                                         "every collision material the same 'exponent'");
        }
    }

    std::vector<Shape> shapes_;
    int ground_body_ = -1;  // the ground's position in the element's bodies (-1: it has no shapes)
    PairFilter filter_;
    ImpactPairs impacts_;
    // the evaluation workspaces (collision_world.hpp): not part of the element's value
    mutable std::mutex pool_mutex_;
    mutable std::vector<std::unique_ptr<World>> pool_;
};

std::unique_ptr<Force> make_collision_contact(const ForceSpec& spec) { return std::make_unique<CollisionContact>(spec); }

}  // namespace
}  // namespace mbd::collision

MBD_FORCE_PLUGIN(collision_contact, mbd::collision::make_collision_contact)

// The keys of the element the core builds from the bodies' `collision:` shapes
// (core/src/scene/scene_collision.cpp); a scene gives them through `collision:`, never directly.
namespace {
const mbd::PluginKey collision_contact_keys[] = {
    {"shapes", "built by the core: one {body, collision} entry per body with `collision:` shapes", nullptr,
     "[{body: a, collision: [{shape: sphere, radius: 0.4, material: {stiffness: 100}}]}, "
     "{body: b, collision: [{shape: sphere, radius: 0.5, material: {stiffness: 100}}]}]"},
    {"joined", "built by the core: the pairs of positions in `shapes` of bodies a joint connects", nullptr, "[]"},
    {}};
}  // namespace

MBD_FORCE_KEYS(collision_contact, "contact between the `collision:` shapes of every body, found by FCL",
               mbd::kEveryBody, mbd::kSpatialOnly, collision_contact_keys)
