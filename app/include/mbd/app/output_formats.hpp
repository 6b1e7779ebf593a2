// The result formats of `mbd simulate --output` (output_sink.hpp), chosen by the file's
// extension: .csv (core/src/output/csv_sink.cpp), .h5 (app/src/hdf5_sink.cpp, if registered). The
// table is app/src/output_formats.cpp, one line per format.
#pragma once

#include <mbd/output_sink.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace mbd {

// Every registered format, in the order of the table.
const std::vector<OutputFormat>& output_formats();

// The format of `path` by its extension; an unknown one throws InputError naming the path,
// the option (`option`, e.g. "--output") and the known extensions.
const OutputFormat& output_format(const std::filesystem::path& path, const std::string& option);

// A sink writing `path` in its format (output_format).
std::unique_ptr<OutputSink> make_output_sink(const std::filesystem::path& path, const std::string& option);

}  // namespace mbd
