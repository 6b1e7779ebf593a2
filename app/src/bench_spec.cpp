// Reading a scene's `bench:` key (bench.hpp, docs/scene-format.md "Benchmarks"): the runs, the
// grids of tolerances and steps, the error measure, the reference and the peers, each refusal at
// the key's file:line.
#include <mbd/app/bench.hpp>

#include <mbd/scene.hpp>
#include <mbd/sdk/number.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace mbd {

namespace {

// Readers of the scene's `bench:` tree (Model::document), each refusal at file:line.
const Param* field(const Param& node, const char* key) {
    const auto it = node.fields.find(key);
    return it == node.fields.end() ? nullptr : &it->second;
}

std::string word(const Param& node, const std::string& what) {
    if (!node.is_scalar()) node.fail("bench: '" + what + "' must be a single word");
    return node.text;
}

std::string word_or(const Param& node, const char* key, const std::string& fallback) {
    const Param* p = field(node, key);
    return p ? word(*p, key) : fallback;
}

std::vector<double> number_list(const Param* node, const std::string& what) {
    std::vector<double> out;
    if (!node) return out;
    if (!node->is_list()) node->fail("bench: '" + what + "' must be a list of numbers");
    for (const Param& item : node->items) out.push_back(item.as_number(what, "bench"));
    return out;
}

void check_keys(const Param& n, const std::string& what, const std::vector<std::string>& accepted);

// A series' grid of tolerances or steps: a list of numbers, or a geometric sequence
// {from: A, to: B, per_decade: N} or {from: A, to: B, ratio: R} from A to B (both included), equal
// ratios between neighbours: 10^(1/N), or the least number of them not above R. Positive values only.
std::vector<double> grid_list(const Param* node, const std::string& what) {
    if (!node || !node->is_map()) {
        std::vector<double> out = number_list(node, what);
        for (size_t k = 0; k < out.size(); ++k)
            if (!(out[k] > 0.0)) node->items[k].fail("bench: '" + what + "' must be positive numbers");
        return out;
    }
    check_keys(*node, what, {"from", "to", "per_decade", "ratio"});
    const Param* from = field(*node, "from");
    const Param* to = field(*node, "to");
    const Param* per_decade = field(*node, "per_decade");
    const Param* ratio = field(*node, "ratio");
    if (!from || !to || (per_decade != nullptr) == (ratio != nullptr))
        node->fail("bench: '" + what + "' as a sequence is {from: A, to: B, per_decade: N} or {from: A, to: B, ratio: R}");
    const double a = from->as_number("from", "bench"), b = to->as_number("to", "bench");
    if (!(a > 0.0) || !(b > 0.0) || a == b)
        node->fail("bench: '" + what + "': 'from' and 'to' must be two different positive numbers");
    double r = per_decade ? std::pow(10.0, 1.0 / per_decade->as_integer("per_decade", 1, 20, "bench"))
                          : ratio->as_number("ratio", "bench");
    if (!(r > 1.0) || !std::isfinite(r)) ratio->fail("bench: '" + what + "': 'ratio' must be a number above 1");
    const double span = std::abs(std::log(a / b)) / std::log(r);
    // rounded up, so that no ratio exceeds R (per_decade spans are whole numbers but for round-off)
    const int intervals = std::max(1, static_cast<int>(std::ceil(span - 1e-9)));
    if (intervals > 200) node->fail("bench: '" + what + "' makes " + std::to_string(intervals + 1) + " points; at most 201");
    std::vector<double> out;
    for (int k = 0; k <= intervals; ++k) out.push_back(a * std::pow(b / a, static_cast<double>(k) / intervals));
    out.back() = b;
    return out;
}

void check_keys(const Param& n, const std::string& what, const std::vector<std::string>& accepted) {
    if (!n.is_map()) n.fail("bench: '" + what + "' must be a map of keys");
    for (const auto& [key, value] : n.fields) {
        if (std::find(accepted.begin(), accepted.end(), key) != accepted.end()) continue;
        std::string list;
        for (const auto& a : accepted) list += (list.empty() ? "'" : ", '") + a + "'";
        value.fail("bench: unknown key '" + key + "' in '" + what + "'; accepted keys are " + list);
    }
}

}  // namespace

namespace {

// `measure:` {body|bodies, point|points, quantity, norm}
BenchMeasure read_measure(const Param& b) {
    const Param* m = field(b, "measure");
    if (!m) b.fail("bench: missing key 'measure' ({body: NAME, quantity: position, norm: max})");
    check_keys(*m, "measure", {"body", "bodies", "point", "points", "quantity", "norm"});
    BenchMeasure measure;
    if (const Param* body = field(*m, "body")) measure.bodies.push_back(word(*body, "body"));
    if (const Param* bodies = field(*m, "bodies")) {
        if (!bodies->is_list()) bodies->fail("bench: 'bodies' must be a list of body names");
        for (const Param& x : bodies->items) measure.bodies.push_back(word(x, "bodies"));
    }
    if (measure.bodies.empty()) m->fail("bench: 'measure' needs 'body' or 'bodies'");
    measure.points.assign(measure.bodies.size(), Eigen::Vector3d::Zero());
    auto read_point = [](const Param& n) {
        const std::vector<double> v = number_list(&n, "point");
        if (v.size() < 2 || v.size() > 3) n.fail("bench: a point is [x, y] or [x, y, z]");
        return Eigen::Vector3d(v[0], v[1], v.size() == 3 ? v[2] : 0.0);
    };
    if (const Param* point = field(*m, "point")) measure.points[0] = read_point(*point);
    if (const Param* points = field(*m, "points")) {
        if (!points->is_list() || points->items.size() != measure.bodies.size())
            points->fail("bench: 'points' needs one point per measured body");
        for (size_t i = 0; i < measure.bodies.size(); ++i) measure.points[i] = read_point(points->items[i]);
    }
    measure.quantity = word_or(*m, "quantity", measure.quantity);
    if (measure.quantity != "position") field(*m, "quantity")->fail("bench: only 'quantity: position' is measured");
    measure.norm = word_or(*m, "norm", measure.norm);
    if (measure.norm != "max" && measure.norm != "final") field(*m, "norm")->fail("bench: 'norm' is max or final");
    return measure;
}

// `reference:` {kind: closed_form|published|tight_run, name, formulation, ..., parameters}
BenchReference read_reference(const Param& b) {
    const Param* r = field(b, "reference");
    if (!r) b.fail("bench: missing key 'reference' ({kind: closed_form|published|tight_run, ...})");
    if (!r->is_map()) r->fail("bench: 'reference' must be a map of keys");
    BenchReference reference;
    reference.kind = word_or(*r, "kind", "");
    for (const auto& [key, value] : r->fields) {
        if (key == "kind") continue;
        if (key == "name") reference.name = word(value, key);
        else if (key == "formulation") reference.formulation = word(value, key);
        else if (key == "integrator") reference.integrator = word(value, key);
        else if (key == "cross_check") reference.cross_check = word(value, key);
        else if (key == "tolerance") reference.tolerance = value.as_number(key, "bench");
        else reference.params[key] = value.as_number(key, "bench");
    }
    if (reference.kind != "closed_form" && reference.kind != "published" && reference.kind != "tight_run")
        r->fail("bench: reference 'kind' is closed_form, published or tight_run");
    return reference;
}

// `runs:` [{formulation, integrator, tolerances|steps}]
std::vector<BenchSeries> read_runs(const Param& b) {
    const Param* runs = field(b, "runs");
    if (!runs || !runs->is_list()) (runs ? runs : &b)->fail("bench: 'runs' must be a list of series");
    std::vector<BenchSeries> list;
    for (const Param& s : runs->items) {
        check_keys(s, "runs", {"formulation", "integrator", "tolerances", "steps"});
        BenchSeries series;
        series.formulation = word_or(s, "formulation", "augmented");
        series.integrator = word_or(s, "integrator", "dopri5");
        series.tolerances = grid_list(field(s, "tolerances"), "tolerances");
        series.steps = grid_list(field(s, "steps"), "steps");
        list.push_back(series);
    }
    return list;
}

// `peers:` {model, simbody: series or list, mujoco: series or list}
void read_peers(const Param& p, BenchSpec& spec) {
    check_keys(p, "peers", {"model", "simbody", "mujoco"});
    spec.peer_model = word_or(p, "model", "");
    for (const char* engine : {"simbody", "mujoco"}) {
        const Param* e = field(p, engine);
        if (!e) continue;
        std::vector<const Param*> list;
        if (e->is_list())
            for (const Param& x : e->items) list.push_back(&x);
        else
            list.push_back(e);
        for (const Param* s : list) {
            check_keys(*s, std::string("peers.") + engine, {"integrator", "tolerances", "steps"});
            BenchPeerSeries ps;
            ps.engine = engine;
            ps.integrator = word_or(*s, "integrator", "default");
            ps.tolerances = grid_list(field(*s, "tolerances"), "tolerances");
            ps.steps = grid_list(field(*s, "steps"), "steps");
            spec.peers.push_back(ps);
        }
    }
}

}  // namespace

BenchSpec load_bench_spec(const Scene& scene) {
    // the scene's `bench:` section as the loader read it (inherited through `base:` like every key)
    const Model& model = scene.model;
    const Param* b = scene.section(kBenchSection);
    if (!b) throw InputError(model.source, "the scene has no 'bench:' key (docs/scene-format.md, Benchmarks)");
    BenchSpec spec;
    spec.scene = model.source;
    spec.name = model.name;
    check_keys(*b, "bench", {"t_end", "output_step", "measure", "reference", "runs", "peers"});
    const Param* t_end = field(*b, "t_end");
    if (!t_end) b->fail("bench: missing key 't_end'");
    spec.t_end = t_end->as_number("t_end", "bench");
    if (const Param* h = field(*b, "output_step")) spec.output_step = h->as_number("output_step", "bench");
    if (!(spec.t_end > 0)) t_end->fail("bench: 't_end' must be positive");
    spec.measure = read_measure(*b);
    spec.reference = read_reference(*b);
    spec.runs = read_runs(*b);
    if (const Param* p = field(*b, "peers")) read_peers(*p, spec);
    return spec;
}

}  // namespace mbd
