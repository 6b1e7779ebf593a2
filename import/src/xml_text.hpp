// The writers' shared XML helpers (mjcf_writer.cpp, urdf_writer.cpp): numbers that read back
// exactly, and one TinyXML element appended to another.
#pragma once

#include <mbd/sdk/rotation.hpp>

#include <tinyxml.h>

#include <cstdio>
#include <string>
#include <vector>

namespace mbd::import::xml {

inline std::string number(double x) {
    if (x == 0.0) return "0";  // also -0
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", x);
    return buffer;
}

inline std::string numbers(const std::vector<double>& values) {
    std::string out;
    for (size_t k = 0; k < values.size(); ++k) out += (k ? " " : "") + number(values[k]);
    return out;
}

inline std::string xyz(const Vec3& v) { return numbers({v.x(), v.y(), v.z()}); }

inline TiXmlElement* child(TiXmlNode* parent, const char* tag) {
    return parent->LinkEndChild(new TiXmlElement(tag))->ToElement();
}

inline std::string document_text(TiXmlDocument& document) {
    TiXmlPrinter printer;
    printer.SetIndent("  ");
    document.Accept(&printer);
    return printer.Str();
}

}  // namespace mbd::import::xml
