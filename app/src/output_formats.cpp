// The table of result formats (output_formats.hpp). A format is registered by one line here
// naming the function that describes it, defined in the format's own file.
#include <mbd/app/output_formats.hpp>

#include <mbd/sdk/params.hpp>

namespace mbd {

namespace {

std::vector<OutputFormat>& registered() {
    static std::vector<OutputFormat> formats;
    return formats;
}

struct Registration {
    explicit Registration(OutputFormat (*describe)()) { registered().push_back(describe()); }
};

}  // namespace

// Declares the format's describing function and adds what it returns to the table.
#define MBD_OUTPUT_FORMAT(describe) \
    OutputFormat describe();        \
    static const Registration registered_##describe(describe)

MBD_OUTPUT_FORMAT(csv_output_format);
MBD_OUTPUT_FORMAT(hdf5_output_format);

const std::vector<OutputFormat>& output_formats() { return registered(); }

const OutputFormat& output_format(const std::filesystem::path& path, const std::string& option) {
    const std::string extension = path.extension().string();
    // a device or FIFO (/dev/stdout, a pipe) named without a format's extension takes the text,
    // written in place (output_file.hpp)
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    const bool stream = !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
                        !std::filesystem::is_directory(status);
    std::string known;
    for (const OutputFormat& format : output_formats())
        if (format.extension == extension) return format;
    for (const OutputFormat& format : output_formats()) {
        if (stream && format.extension == ".csv") return format;
        known += (known.empty() ? "" : ", ") + format.extension + " (" + format.description + ")";
    }
    const std::string given = extension.empty() ? "it has none" : "'" + extension + "' is none of them";
    throw InputError(path.string(), option + ": the format is chosen by the file's extension, and " + given +
                                        "; known: " + known);
}

std::unique_ptr<OutputSink> make_output_sink(const std::filesystem::path& path, const std::string& option) {
    return output_format(path, option).make(path);
}

}  // namespace mbd
