// The contacts of a run for output (contact_output.hpp).
#include <mbd/body_poses.hpp>
#include <mbd/contact_output.hpp>
#include <mbd/csv.hpp>

#include <utility>

namespace mbd {

struct ContactProbe::Poses {
    explicit Poses(const Model& model) : poses(model) {}
    BodyPoses poses;
    BodyStates view;
};

ContactProbe::ContactProbe(const Model& model) : model_(model), poses_(std::make_unique<Poses>(model)) {
    for (const ForceInstance& f : model.forces)
        if (const auto* reporter = dynamic_cast<const ContactReporter*>(f.force.get()))
            elements_.push_back({reporter, &f.bodies});
}

ContactProbe::~ContactProbe() = default;

std::vector<ContactReport> ContactProbe::contacts(const State& state) const {
    std::vector<ContactReport> all;
    poses_->poses.update(state);
    for (const Element& e : elements_) {
        poses_->poses.fill(*e.bodies, state.t, poses_->view);
        for (ContactReport r : e.reporter->contacts(poses_->view)) {
            r.body_i = (*e.bodies)[r.body_i];  // element position -> model body (kGround stays)
            r.body_j = (*e.bodies)[r.body_j];
            if (r.body_i > r.body_j) {  // one order whatever the detection's: body i the smaller index
                std::swap(r.body_i, r.body_j);
                r.normal = -r.normal;  // the normal force on the new j is the same along the new normal
                r.friction_force = -r.friction_force;
                r.rolling_torque = -r.rolling_torque;
            }
            all.push_back(r);
        }
    }
    return all;
}

std::vector<ContactReport> ContactProbe::contacts_at_row(const double* row) const {
    return contacts(motion_state(model_, row));
}

std::vector<std::string> contact_columns() {
    return {"t", "body_i", "body_j", "x", "y", "z", "nx", "ny", "nz", "depth", "normal_force", "friction_x",
            "friction_y", "friction_z", "rolling_x", "rolling_y", "rolling_z"};
}

namespace {

class ContactSink : public OutputSink {
public:
    ContactSink(const Model& model, std::unique_ptr<OutputSink> table) : probe_(model), table_(std::move(table)) {
        motion_ = motion_columns(model);
    }

    void begin(const std::vector<std::string>& columns) override {
        if (columns.size() < motion_.size() || !std::equal(motion_.begin(), motion_.end(), columns.begin()))
            throw std::invalid_argument("the contact sink needs rows that begin with the motion columns");
        table_->begin(contact_columns());
    }
    void row(const std::vector<double>& values) override {
        for (const ContactReport& c : probe_.contacts_at_row(values.data())) {
            const double i = c.body_i, j = c.body_j;  // kGround is -1, as the table says
            table_->row({values[0], i, j, c.point.x(), c.point.y(), c.point.z(), c.normal.x(), c.normal.y(),
                         c.normal.z(), c.depth, c.normal_force, c.friction_force.x(), c.friction_force.y(),
                         c.friction_force.z(), c.rolling_torque.x(), c.rolling_torque.y(), c.rolling_torque.z()});
        }
    }
    void end() override { table_->end(); }

    bool reports() const { return probe_.reports(); }

private:
    ContactProbe probe_;
    std::unique_ptr<OutputSink> table_;
    std::vector<std::string> motion_;
};

}  // namespace

std::unique_ptr<OutputSink> make_contact_sink(const Model& model, std::unique_ptr<OutputSink> table,
                                              const std::string& option) {
    auto sink = std::make_unique<ContactSink>(model, std::move(table));
    if (!sink->reports())
        throw InputError(option, "the scene '" + model.name +
                                     "' has no contacts to write: only bodies with `collision:` shapes report theirs "
                                     "(docs/scene-format.md \"Collision shapes\")");
    return sink;
}

}  // namespace mbd
