// Motion output in the CSV contract: t, then per body NAME.x NAME.y NAME.angle
// (planar) or NAME.x NAME.y NAME.z NAME.e0..e3 (spatial), then per body
// NAME.vx NAME.vy NAME.omega or NAME.vx NAME.vy NAME.vz NAME.wx NAME.wy NAME.wz
// (world axes), then per node K of each flexible body NAME.nodeK.x NAME.nodeK.y
// (.z) NAME.nodeK.vx NAME.nodeK.vy (.vz), world. Values are written with 17 significant digits; a non-finite
// value is refused (the writer throws) so that no NaN reaches a result file.
#pragma once

#include <mbd/model.hpp>

#include <mbd/output_file.hpp>

#include <string>
#include <vector>

namespace mbd {

std::vector<std::string> motion_columns(const Model& model);
std::vector<double> motion_values(const Model& model, const State& state);
// The state a row of motion_values holds (its first motion_columns(model).size() values): the
// inverse of motion_values, the Euler parameters as written (world angular velocities turned
// back into body axes).
State motion_state(const Model& model, const double* values);

// A CSV result file in the output contract of output_file.hpp: PATH.partial while
// the rows come in, PATH after close(); destroyed without close() (a failed or
// interrupted run), the complete rows stay in PATH.partial.
class CsvWriter {
public:
    CsvWriter(const std::string& path, const std::vector<std::string>& columns);
    ~CsvWriter();
    void row(const std::vector<double>& values);
    void close();
    long rows() const { return file_.records(); }
    const std::filesystem::path& path() const { return file_.path(); }

private:
    static std::string header(const std::vector<std::string>& columns);

    OutputFile file_;
    size_t columns_;
    bool timed_;            // the first column is t
    double last_time_ = 0.0;
    std::string line_;      // scratch for one row
};

}  // namespace mbd
