// The contacts of a run, for output (docs/user-guide.md "Contacts"): every active contact of the
// force elements that report theirs (mbd/sdk/contact_report.hpp; the collision element), at a
// state or at an output row, and the output sink `mbd simulate --contacts FILE` writes them with.
//
// The contact table has one row per contact and output time (a time without contacts has no
// row), in the columns of contact_columns():
//   t, body_i, body_j       the two bodies: their positions in the scene's `bodies:` (from 0),
//                           -1 for the ground; body_i < body_j
//   x, y, z                 the contact point, world
//   nx, ny, nz              the unit normal, from body_i toward body_j
//   depth                   the penetration (> 0)
//   normal_force            the normal force on body_j along n (> 0: pushing the bodies apart)
//   friction_x, _y, _z      the friction force on body_j (tangential), world
// Body i carries the opposite forces.
#pragma once

#include <mbd/model.hpp>
#include <mbd/output_sink.hpp>
#include <mbd/sdk/contact_report.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

// The contacts of a model's reporting elements; body_i, body_j of its reports are model body
// indices (kGround for the ground), body_i < body_j. Not for concurrent use (one pose workspace).
class ContactProbe {
public:
    explicit ContactProbe(const Model& model);
    ~ContactProbe();
    // Some force element reports contacts (the scene has collision shapes).
    bool reports() const { return !elements_.empty(); }
    std::vector<ContactReport> contacts(const State& state) const;
    // At an output row whose first values are the motion columns (csv.hpp motion_values).
    std::vector<ContactReport> contacts_at_row(const double* row) const;

private:
    struct Element {
        const ContactReporter* reporter;
        const std::vector<int>* bodies;  // model body indices of the element's positions
    };
    const Model& model_;
    std::vector<Element> elements_;
    struct Poses;
    std::unique_ptr<Poses> poses_;
};

std::vector<std::string> contact_columns();

// A sink taking a run's rows (motion columns first) and writing their contacts, a row each, to
// `table` (a CSV or HDF5 sink of output_formats.hpp), which it begins, feeds and ends. A model
// without a reporting element throws InputError naming `option` (nothing to write).
std::unique_ptr<OutputSink> make_contact_sink(const Model& model, std::unique_ptr<OutputSink> table,
                                              const std::string& option);

}  // namespace mbd
