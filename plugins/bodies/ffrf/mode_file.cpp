#include "mode_file.hpp"

#include <mbd/sdk/number.hpp>
#include <mbd/sdk/params.hpp>

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

namespace mbd::ffrf {

namespace {

// The file's meaningful lines (comments and blanks skipped), each with its line number.
class Lines {
public:
    // `where`: the file:line of the key that names the file (where a missing file is reported)
    Lines(const std::string& path, const std::string& owner, const std::string& where)
        : path_(path), owner_(owner), in_(path) {
        if (!in_)
            throw InputError(where, owner + ": cannot open the mode file '" + path +
                                        "' (give 'mode_file' relative to the scene file's folder, or an absolute path)");
    }
    // The next line's words; `what` says what was expected, for the message at the end of file.
    std::vector<std::string> next(const std::string& what) {
        std::string text;
        while (std::getline(in_, text)) {
            ++line_;
            const auto hash = text.find('#');
            if (hash != std::string::npos) text.resize(hash);
            std::istringstream words(text);
            std::vector<std::string> out;
            for (std::string w; words >> w;) out.push_back(w);
            if (!out.empty()) return out;
        }
        fail("the file ends where " + what + " was expected");
    }
    bool at_end() {
        std::streampos here = in_.tellg();
        const int line = line_;
        std::string text;
        while (std::getline(in_, text)) {
            const auto hash = text.find('#');
            if (hash != std::string::npos) text.resize(hash);
            if (text.find_first_not_of(" \t\r") != std::string::npos) {
                in_.clear();
                in_.seekg(here);
                line_ = line;
                return false;
            }
        }
        return true;
    }
    // The line's words as `count` numbers (`what` names them for the message).
    std::vector<double> numbers(const std::vector<std::string>& words, size_t first, size_t count,
                                const std::string& what) {
        if (words.size() != first + count)
            fail("expected " + what + ", got " + std::to_string(words.size() - first) + " values");
        std::vector<double> out(count);
        for (size_t k = 0; k < count; ++k)
            if (parse_number(words[first + k], out[k]) != NumberText::Valid)
                fail("'" + words[first + k] + "' is not a number (expected " + what + ")");
        return out;
    }
    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(path_ + ":" + std::to_string(line_), owner_ + ": mode file: " + message);
    }

private:
    std::string path_, owner_;
    std::ifstream in_;
    int line_ = 0;
};

struct Node {
    Eigen::Vector2d u0;
    double mass;
};

std::vector<Node> read_nodes(Lines& lines) {
    const auto head = lines.next("'nodes N'");
    if (head.size() != 2 || head[0] != "nodes") lines.fail("the file must begin with 'nodes N'");
    const double count = lines.numbers(head, 1, 1, "the number of nodes")[0];
    if (!(count >= 1 && count <= 1e6 && count == std::floor(count)))
        lines.fail("the number of nodes must be a whole number of at least 1");
    std::vector<Node> nodes(static_cast<size_t>(count));
    for (Node& node : nodes) {
        const auto v = lines.numbers(lines.next("a node's 'x y mass'"), 0, 3, "'x y mass'");
        if (!(v[2] >= 0)) lines.fail("a node's mass must not be negative");
        node = {Eigen::Vector2d(v[0], v[1]), v[2]};
    }
    return nodes;
}

}  // namespace

ModalModel read_mode_file(const std::string& path, const std::string& owner, const std::string& where) {
    Lines lines(path, owner, where);
    const std::vector<Node> nodes = read_nodes(lines);
    std::vector<double> modal_mass, modal_stiffness;
    std::vector<Eigen::MatrixXd> shapes;  // per mode: 3 x nodes (ux, uy, rotation)
    while (!lines.at_end()) {
        const auto head = lines.next("'mode MASS STIFFNESS'");
        if (head[0] != "mode") lines.fail("expected 'mode MASS STIFFNESS' after the nodes or a mode's lines");
        const auto v = lines.numbers(head, 1, 2, "'mode MASS STIFFNESS'");
        if (!(v[0] > 0)) lines.fail("the modal mass must be positive, got " + head[1]);
        if (!(v[1] >= 0)) lines.fail("the modal stiffness must not be negative, got " + head[2]);
        modal_mass.push_back(v[0]);
        modal_stiffness.push_back(v[1]);
        Eigen::MatrixXd shape(3, nodes.size());
        for (size_t k = 0; k < nodes.size(); ++k) {
            const auto u = lines.numbers(lines.next("a node's 'ux uy rotation'"), 0, 3, "'ux uy rotation'");
            shape.col(static_cast<Eigen::Index>(k)) << u[0], u[1], u[2];
        }
        shapes.push_back(shape);
    }
    const int m = static_cast<int>(shapes.size());
    if (m == 0) lines.fail("the file has no mode ('mode MASS STIFFNESS' and one line per node)");

    auto points = std::make_shared<std::vector<ModalPoint>>(nodes.size());
    ModalModel model(m);
    for (size_t k = 0; k < nodes.size(); ++k) {
        ModalPoint& point = (*points)[k];
        point.u0 = nodes[k].u0;
        point.S.resize(2, m);
        point.rotation.resize(m);
        for (int i = 0; i < m; ++i) {
            point.S.col(i) = shapes[i].block<2, 1>(0, static_cast<Eigen::Index>(k));
            point.rotation[i] = shapes[i](2, static_cast<Eigen::Index>(k));
        }
        model.add_mass(nodes[k].mass, point);
        model.nodes.push_back(static_cast<double>(k));
    }
    if (!(model.mass > 0)) lines.fail("the nodes' masses add up to zero: give each node its lumped mass");
    model.Mff = Eigen::Map<Eigen::VectorXd>(modal_mass.data(), m).asDiagonal();
    model.Kff = Eigen::Map<Eigen::VectorXd>(modal_stiffness.data(), m).asDiagonal();
    model.lowest = 0.0;
    model.highest = static_cast<double>(nodes.size() - 1);
    model.parameter = "node index";
    model.whole_parameter = true;
    model.at = [points](double index) { return (*points)[static_cast<size_t>(std::lround(index))]; };
    return model;
}

}  // namespace mbd::ffrf
