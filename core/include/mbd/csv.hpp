// Motion output in the CSV contract: t, then per body NAME.x NAME.y NAME.angle
// (planar) or NAME.x NAME.y NAME.z NAME.e0..e3 (spatial), then per body
// NAME.vx NAME.vy NAME.omega or NAME.vx NAME.vy NAME.vz NAME.wx NAME.wy NAME.wz
// (world axes). Values are written with 17 significant digits; a non-finite
// value is refused (the writer throws) so that no NaN reaches a result file.
#pragma once

#include <mbd/model.hpp>

#include <fstream>
#include <string>
#include <vector>

namespace mbd {

std::vector<std::string> motion_columns(const Model& model);
std::vector<double> motion_values(const Model& model, const State& state);

class CsvWriter {
public:
    // Writes to PATH.partial and renames to PATH on close(), so a reader never
    // sees a half-written file under the final name.
    CsvWriter(const std::string& path, const std::vector<std::string>& columns);
    ~CsvWriter();
    void row(const std::vector<double>& values);
    void close();

private:
    std::string path_;
    std::string partial_;
    std::ofstream out_;
    size_t columns_;
    bool closed_ = false;
};

}  // namespace mbd
