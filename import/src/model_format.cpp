// Format detection (model_format.hpp): the XML prolog (declaration, comments, doctype) is
// skipped and the root element's name read; no XML is interpreted beyond that.
#include <mbd/import/model_format.hpp>

#include <mbd/sdk/params.hpp>  // InputError

#include <cctype>
#include <fstream>

namespace mbd::import {

namespace {

// The name of the first element of `text`, "" when the text does not start like XML.
std::string root_element(const std::string& text) {
    size_t at = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // UTF-8 byte order mark
    for (;;) {
        while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
        if (at >= text.size() || text[at] != '<') return "";
        if (text.compare(at, 4, "<!--") == 0) {
            const size_t end = text.find("-->", at + 4);
            if (end == std::string::npos) return "";
            at = end + 3;
        } else if (text.compare(at, 2, "<?") == 0 || text.compare(at, 2, "<!") == 0) {
            const size_t end = text.find('>', at + 2);
            if (end == std::string::npos) return "";
            at = end + 1;
        } else {
            size_t end = at + 1;
            while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end])) && text[end] != '>' &&
                   text[end] != '/')
                ++end;
            return text.substr(at + 1, end - at - 1);
        }
    }
}

}  // namespace

ModelFormat detect_format(const std::filesystem::path& file) {
    // what is not a readable regular file (missing, a folder, a FIFO) is left to the scene
    // loader, whose messages say why it cannot be read
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) return ModelFormat::Scene;
    std::ifstream in(file, std::ios::binary);
    if (!in) return ModelFormat::Scene;
    std::string head(1 << 16, '\0');  // a prolog of licence comments fits
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    const std::string root = root_element(head);
    if (root.empty()) return ModelFormat::Scene;
    if (root == "mujoco") return ModelFormat::Mjcf;
    if (root == "robot") return ModelFormat::Urdf;
    if (root == "sdf") return ModelFormat::Sdf;
    throw InputError(file.string(), "an XML file whose root element is <" + root +
                                        ">: mbd reads MJCF (<mujoco>), URDF (<robot>), SDF (<sdf>) and its own YAML scenes");
}

std::string format_name(ModelFormat format) {
    switch (format) {
        case ModelFormat::Mjcf: return "MJCF";
        case ModelFormat::Urdf: return "URDF";
        case ModelFormat::Sdf: return "SDF";
        case ModelFormat::Scene: break;
    }
    return "mbd scene";
}

}  // namespace mbd::import
