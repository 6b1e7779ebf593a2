// Reading and checking a study file (study.hpp, docs/sweep.md).
#include <mbd/app/study.hpp>

#include <mbd/app/study_case.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/integrator.hpp>
#include <mbd/scene.hpp>
#include <mbd/scene_parameters.hpp>
#include <mbd/statics_analysis.hpp>
#include <mbd/sdk/suggest.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace mbd {

namespace {

std::string listed(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// "did you mean 'x'? (known: a, b, c)" for a name not among `known`.
std::string suggestion(const std::string& name, const std::vector<std::string>& known) {
    const std::string nearest = nearest_name(name, known);
    return (nearest.empty() ? std::string() : "did you mean '" + nearest + "'? ") + "(known: " + listed(known) + ")";
}

// Refuses a key of `node` (a map) that is not in `allowed`, at its line.
void check_keys(const Param& node, const std::string& owner, const std::vector<std::string>& allowed) {
    for (const auto& [key, value] : node.fields)
        if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
            value.fail(owner + ": unknown key '" + key + "'; " + suggestion(key, allowed));
}

const Param& require_map(const Param& node, const std::string& what) {
    if (!node.is_map()) node.fail("'" + what + "' must be a map of keys");
    return node;
}

const Param* field(const Param& map, const std::string& key) {
    auto it = map.fields.find(key);
    return it == map.fields.end() ? nullptr : &it->second;
}

const Param& required(const Param& map, const std::string& key, const std::string& owner) {
    const Param* p = field(map, key);
    if (!p) map.fail(owner + ": missing key '" + key + "'");
    return *p;
}

std::string word(const Param& p, const std::string& key) {
    if (!p.is_scalar() || p.text.empty()) p.fail("'" + key + "' must be a single word");
    return p.text;
}

std::string one_of(const Param& p, const std::string& key, const std::vector<std::string>& allowed) {
    const std::string w = word(p, key);
    if (std::find(allowed.begin(), allowed.end(), w) == allowed.end())
        p.fail("'" + key + "': unknown value '" + w + "'; " + suggestion(w, allowed));
    return w;
}

double positive(const Param& p, const std::string& key) {
    const double v = p.as_number(key);
    if (!(v > 0.0)) p.fail("'" + key + "' must be positive, got " + p.text);
    return v;
}

StudyAnalysis read_analysis(const Param& node) {
    require_map(node, "analysis");
    StudyAnalysis a;
    const std::string type = one_of(required(node, "type", "analysis"), "analysis.type",
                                    {"simulate", "statics", "inverse", "modes"});
    const std::map<std::string, AnalysisType> types{{"simulate", AnalysisType::Simulate},
                                                    {"statics", AnalysisType::Statics},
                                                    {"inverse", AnalysisType::Inverse},
                                                    {"modes", AnalysisType::Modes}};
    a.type = types.at(type);
    const std::vector<std::string> statics_keys{"type", "time", "tolerance", "max_iterations", "objective", "solver"};
    switch (a.type) {
    case AnalysisType::Simulate:
        check_keys(node, "analysis (simulate)",
                   {"type", "t_end", "formulation", "integrator", "tol", "step", "output_step"});
        a.run.t_end = positive(required(node, "t_end", "analysis (simulate)"), "t_end");
        if (const Param* p = field(node, "formulation")) a.run.formulation = word(*p, "formulation");
        if (const Param* p = field(node, "integrator")) a.run.integrator = word(*p, "integrator");
        if (const Param* p = field(node, "tol")) a.run.integration.tolerance = positive(*p, "tol");
        if (const Param* p = field(node, "step")) a.run.integration.step = positive(*p, "step");
        if (const Param* p = field(node, "output_step")) a.run.output_step = positive(*p, "output_step");
        if (field(node, "tol") && field(node, "step"))
            node.fail("analysis: give 'tol' (adaptive) or 'step' (fixed), not both");
        break;
    case AnalysisType::Inverse:
        check_keys(node, "analysis (inverse)", {"type", "t_end", "step", "solver"});
        a.run.t_end = positive(required(node, "t_end", "analysis (inverse)"), "t_end");
        a.run.integration.step = positive(required(node, "step", "analysis (inverse)"), "step");
        if (const Param* p = field(node, "solver")) a.solver = word(*p, "solver");
        break;
    case AnalysisType::Statics:
    case AnalysisType::Modes: {
        std::vector<std::string> keys = statics_keys;
        if (a.type == AnalysisType::Modes) keys.push_back("about");
        check_keys(node, "analysis (" + type + ")", keys);
        if (const Param* p = field(node, "time")) a.time = p->as_number("time");
        if (const Param* p = field(node, "tolerance")) a.statics_tolerance = positive(*p, "tolerance");
        if (const Param* p = field(node, "max_iterations"))
            a.max_iterations = static_cast<int>(p->as_integer("max_iterations", 1, 1000000));
        if (const Param* p = field(node, "objective"))
            a.objective = one_of(*p, "objective", {"auto", "potential", "virtual-work"});
        if (const Param* p = field(node, "solver")) a.solver = word(*p, "solver");
        if (const Param* p = field(node, "about")) a.about = one_of(*p, "about", {"statics", "initial"});
        break;
    }
    }
    return a;
}

// The analysis's options checked once, on the base scene, by the checks its command makes
// (`mbd simulate`: check_integrator_options and check_simulation_method; `mbd inverse`:
// check_inverse_dynamics; the solver by the registry), so that a wrong option is refused
// before any case rather than failing every case. The error is placed at the key it names
// (the study file's line), else at the analysis's `type`.
void check_analysis(const Param& node, const StudyAnalysis& a, const Model& model, Registry& registry) {
    auto spell = [](const std::string& option, const std::string& value) {
        std::string key = option;
        std::replace(key.begin(), key.end(), '-', '_');
        return value.empty() ? "'" + key + "'" : key + ": " + value;
    };
    try {
        switch (a.type) {
        case AnalysisType::Simulate: {
            check_integrator_options(a.run.integrator, field(node, "tol") != nullptr, a.run.integration.tolerance,
                                     field(node, "step") != nullptr, a.run.integration.step, a.run.t_end, spell);
            SimulationSettings quiet = a.run;
            quiet.messages = MessageLog::silent();
            check_simulation_method(model, registry, quiet);
            break;
        }
        case AnalysisType::Inverse:
            check_inverse_dynamics(model);
            registry.create_inverse(InverseSpec{a.solver, a.solver, {}}, "analysis.solver");
            break;
        case AnalysisType::Statics:
        case AnalysisType::Modes: registry.create_statics(StaticsSpec{a.solver, a.solver, {}}, "analysis.solver"); break;
        }
    } catch (const InputError& e) {
        std::string key = e.where();
        if (key.size() > 2 && key.front() == '\'' && key.back() == '\'') key = key.substr(1, key.size() - 2);
        if (!field(node, key))  // else the key whose value the message quotes (an unknown formulation)
            for (const auto& [name, value] : node.fields)
                if (name != "type" && value.is_scalar() && e.message().find("'" + value.text + "'") != std::string::npos)
                    key = name;
        if (const Param* at = field(node, key)) at->fail("analysis: '" + key + "': " + e.message());
        required(node, "type", "analysis").fail("analysis (" + analysis_name(a.type) + "): " + e.what() +
                                               "; every case would fail, so none is run");
    }
}

// A design's value list: `values: [...]` or `range: [lo, hi]` with `count: n` (n >= 2, even spacing).
std::vector<double> grid_values(const Param& node, const std::string& owner) {
    const Param* values = field(node, "values");
    const Param* range = field(node, "range");
    if (values) {
        if (range) node.fail(owner + ": give 'values' or 'range' with 'count', not both");
        const Eigen::VectorXd v = values->as_vector("values");
        if (v.size() == 0) values->fail(owner + ": 'values' is empty");
        return std::vector<double>(v.data(), v.data() + v.size());
    }
    if (!range) node.fail(owner + ": a grid needs 'values: [...]' or 'range: [lo, hi]' with 'count: n'");
    const Eigen::VectorXd r = range->as_vector("range", 2);
    const long long n = required(node, "count", owner).as_integer("count", 1, 1000000);
    std::vector<double> out(static_cast<size_t>(n));
    for (long long k = 0; k < n; ++k)
        out[k] = n == 1 ? r[0] : r[0] + (r[1] - r[0]) * static_cast<double>(k) / static_cast<double>(n - 1);
    return out;
}

// A distribution for Latin hypercube and Monte Carlo designs.
void read_distribution(const Param& node, const std::string& owner, StudyParameter& p) {
    const Param* d = field(node, "distribution");
    p.distribution = d ? one_of(*d, "distribution", {"uniform", "normal", "lognormal", "triangular"}) : "uniform";
    if (p.distribution == "uniform") {
        check_keys(node, owner, {"path", "distribution", "range"});
        const Param& range = required(node, "range", owner);
        const Eigen::VectorXd r = range.as_vector("range", 2);
        if (!(r[1] > r[0])) range.fail(owner + ": 'range' must be [lo, hi] with lo < hi");
        p.a = r[0];
        p.b = r[1];
    } else if (p.distribution == "normal" || p.distribution == "lognormal") {
        const bool log = p.distribution == "lognormal";
        const std::string centre = log ? "mu" : "mean", spread = log ? "sigma" : "sd";
        check_keys(node, owner, {"path", "distribution", centre, spread});
        p.a = required(node, centre, owner).as_number(centre);
        p.b = positive(required(node, spread, owner), spread);
    } else {
        check_keys(node, owner, {"path", "distribution", "lower", "mode", "upper"});
        p.a = required(node, "lower", owner).as_number("lower");
        p.b = required(node, "mode", owner).as_number("mode");
        p.c = required(node, "upper", owner).as_number("upper");
        if (!(p.a <= p.b && p.b <= p.c && p.a < p.c))
            node.fail(owner + ": a triangular distribution needs lower <= mode <= upper, lower < upper");
    }
}

StudyDesign read_design(const Param& node) {
    require_map(node, "design");
    StudyDesign d;
    const std::string type =
        one_of(required(node, "type", "design"), "design.type", {"grid", "latin_hypercube", "monte_carlo"});
    if (type == "grid") {
        check_keys(node, "design (grid)", {"type"});
        d.type = DesignType::Grid;
        return d;
    }
    check_keys(node, "design (" + type + ")", {"type", "cases", "seed"});
    d.type = type == "latin_hypercube" ? DesignType::LatinHypercube : DesignType::MonteCarlo;
    d.cases = static_cast<long>(required(node, "cases", "design").as_integer("cases", 1, 100000000));
    if (const Param* s = field(node, "seed"))
        d.seed = static_cast<unsigned long long>(s->as_integer("seed", 0, 9007199254740992LL));
    return d;
}

// The path must name a number of the scene, or a key the scene leaves out but may have (an
// initial velocity): such a key is set on a copy and the scene built, and an "unknown key"
// about it is the path's error. Other problems of that value are left to the cases.
void check_parameter_path(const Param& item, const StudyParameter& p, const Param& scene_document,
                          Registry& registry) {
    bool present = true;
    try {
        scene_parameter(scene_document, p.path);
    } catch (const ParameterError&) {
        present = false;
    }
    Param copy = scene_document;
    try {
        set_scene_parameter(copy, p.path, p.values.empty() ? inverse_cdf(p, 0.5) : p.values.front());
    } catch (const ParameterError& e) {
        item.fail(e.message() + " (in the base scene " + e.where() + ")");
    }
    if (present) return;
    std::string key = p.path.substr(p.path.find_last_of('.') + 1);
    key = key.substr(0, key.find('['));
    try {
        load_scene_document(copy, scene_document.file, registry);
    } catch (const InputError& e) {
        if (e.message().find("unknown key '" + key + "'") != std::string::npos)
            item.fail("parameter '" + p.path + "': " + e.message() + " (the base scene " + e.where() + ")");
    }
}

std::vector<StudyParameter> read_parameters(const Param& node, const StudyDesign& design, const Param& scene_document,
                                            Registry& registry) {
    if (!node.is_list() || node.items.empty())
        node.fail("'parameters' must be a list of {path: KEY, ...}, one item per varied scene key");
    std::vector<StudyParameter> out;
    for (size_t k = 0; k < node.items.size(); ++k) {
        const Param& item = require_map(node.items[k], "parameters[" + std::to_string(k) + "]");
        StudyParameter p;
        p.where = item.location();
        p.path = word(required(item, "path", "parameters[" + std::to_string(k) + "]"), "path");
        const std::string owner = "parameter '" + p.path + "'";
        for (const StudyParameter& earlier : out)
            if (earlier.path == p.path) item.fail(owner + " is varied twice (also at " + earlier.where + ")");
        if (design.type == DesignType::Grid) {
            check_keys(item, owner, {"path", "values", "range", "count"});
            p.values = grid_values(item, owner);
        } else {
            read_distribution(item, owner, p);
        }
        check_parameter_path(item, p, scene_document, registry);
        out.push_back(std::move(p));
    }
    return out;
}

std::vector<StudyMetric> read_metrics(const Param& node, const std::vector<std::string>& columns) {
    if (!node.is_list() || node.items.empty())
        node.fail("'metrics' must be a list of {final|max|min|rms: COLUMN} items");
    const std::vector<std::string> reductions{"final", "max", "min", "rms"};
    std::vector<StudyMetric> out;
    for (const Param& item : node.items) {
        if (!item.is_map() || item.fields.size() != 1)
            item.fail("a metric is one key, the reduction, with the column: {max: bob.y}");
        const auto& [key, value] = *item.fields.begin();
        StudyMetric m;
        m.where = value.location();
        if (std::find(reductions.begin(), reductions.end(), key) == reductions.end())
            value.fail("unknown metric '" + key + "'; " + suggestion(key, reductions));
        m.reduction = key == "final" ? Reduction::Final
                      : key == "max" ? Reduction::Max
                      : key == "min" ? Reduction::Min
                                     : Reduction::Rms;
        m.column = word(value, key);
        if (std::find(columns.begin(), columns.end(), m.column) == columns.end())
            value.fail("metric '" + key + "': the results have no column '" + m.column + "'; " +
                       suggestion(m.column, columns));
        m.name = key + "(" + m.column + ")";
        for (const StudyMetric& earlier : out)
            if (earlier.name == m.name) value.fail("metric " + m.name + " is asked for twice");
        out.push_back(std::move(m));
    }
    return out;
}

std::vector<std::string> read_series(const Param& node, const StudyAnalysis& analysis,
                                     const std::vector<std::string>& columns) {
    if (analysis.type != AnalysisType::Simulate && analysis.type != AnalysisType::Inverse)
        node.fail("'series' is for time histories: analysis simulate or inverse, not " + analysis_name(analysis.type));
    if (!node.is_list() || node.items.empty()) node.fail("'series' must be a list of columns, e.g. [t, bob.x]");
    std::vector<std::string> out;
    for (const Param& item : node.items) {
        const std::string c = word(item, "series");
        if (std::find(columns.begin(), columns.end(), c) == columns.end())
            item.fail("series: the results have no column '" + c + "'; " + suggestion(c, columns));
        out.push_back(c);
    }
    return out;
}

std::string file_text(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot read the study file");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

std::string reduction_name(Reduction r) {
    switch (r) {
    case Reduction::Final: return "final";
    case Reduction::Max: return "max";
    case Reduction::Min: return "min";
    case Reduction::Rms: return "rms";
    }
    return "final";
}

std::string analysis_name(AnalysisType a) {
    switch (a) {
    case AnalysisType::Simulate: return "simulate";
    case AnalysisType::Statics: return "statics";
    case AnalysisType::Inverse: return "inverse";
    case AnalysisType::Modes: return "modes";
    }
    return "simulate";
}

Study read_study(const std::filesystem::path& file, Registry& registry, const SceneLoader& load) {
    Study s;
    s.file = file;
    s.text = file_text(file);
    const Param root = read_scene_document(file);
    require_map(root, "study");
    check_keys(root, "study", {"scene", "analysis", "parameters", "design", "metrics", "series"});
    const Param& scene = required(root, "scene", "study");
    s.scene = word(scene, "scene");
    if (s.scene.is_relative()) s.scene = file.parent_path() / s.scene;
    s.model = std::make_shared<const Model>(load_with(load, s.scene, registry).model);
    s.analysis = read_analysis(required(root, "analysis", "study"));
    check_analysis(required(root, "analysis", "study"), s.analysis, *s.model, registry);
    s.design = read_design(required(root, "design", "study"));
    s.parameters = read_parameters(required(root, "parameters", "study"), s.design, *s.model->document, registry);
    s.columns = case_columns(*s.model, s.analysis);
    s.metrics = read_metrics(required(root, "metrics", "study"), s.columns);
    if (const Param* series = field(root, "series")) s.series = read_series(*series, s.analysis, s.columns);
    return s;
}

}  // namespace mbd
