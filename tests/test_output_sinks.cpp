// The output sinks of a run (core/include/mbd/output_sink.hpp, issue 43 item 4): the simulate
// driver hands every row to each sink it is given. The in-memory sink holds the CSV's rows bit
// for bit; a failed run ends no sink; `simulate --animation` takes its frames from the run's
// rows (no CSV read back), so its animation is byte for byte the one `mbd animate` makes from
// the CSV of the same run.
#include <gtest/gtest.h>

#include <mbd/output_file.hpp>
#include <mbd/simulation.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::read_text;
using mbd::test::run_mbd;
using mbd::test::scratch;

// The CSV's cells through the tests' reader (std::stod: 17 digits read back exactly), row-major.
std::vector<double> csv_values(const fs::path& file, std::vector<std::string>& header) {
    const mbd::test::Csv csv = mbd::test::read_csv(file);
    header = csv.header;
    std::vector<double> values;
    for (const auto& row : csv.rows) values.insert(values.end(), row.begin(), row.end());
    return values;
}

TEST(MemorySink, HoldsTheRowsTheCsvSinkWritesBitForBit) {
    const fs::path dir = scratch("memory");
    const mbd::Model model = mbd::test::load("dynamics/four-bar-spring-damper.yaml");
    mbd::SimulationSettings s = mbd::test::adaptive_run("augmented", "dopri5", 1e-8, 1.0, 0.01);
    s.reactions = s.diagnostics = true;
    mbd::MemorySink memory;
    const std::unique_ptr<mbd::OutputSink> csv = mbd::csv_output_format().make(dir / "r.csv");
    const mbd::SimulationResult r = mbd::simulate(model, mbd::test::shared_registry(), s, {}, {&memory, csv.get()});
    EXPECT_TRUE(memory.complete());
    ASSERT_EQ(memory.rows(), static_cast<std::size_t>(r.rows));
    EXPECT_EQ(memory.rows(), 101u);
    EXPECT_EQ(memory.columns(), r.columns);
    std::vector<std::string> header;
    const std::vector<double> values = csv_values(dir / "r.csv", header);
    EXPECT_EQ(header, memory.columns());
    ASSERT_EQ(values.size(), memory.values().size());
    EXPECT_EQ(std::memcmp(values.data(), memory.values().data(), values.size() * sizeof(double)), 0);
    EXPECT_EQ(memory.at(100, 0), 1.0);  // the last row is at t_end
}

// A run that diverges ends no sink: the memory sink is not complete and the CSV keeps its rows
// in r.csv.partial, with nothing under r.csv (output_file.hpp).
TEST(MemorySink, AFailedRunEndsNoSink) {
    const fs::path dir = scratch("failed");
    const mbd::Model model = mbd::test::load("dynamics/pendulum-a01.yaml");
    mbd::SimulationSettings s = mbd::test::adaptive_run("augmented", "rk4", 1e-6, 200.0, 2.0);
    s.integrator = "rk4";
    s.integration.step = 2.0;  // far too large a step: the motion diverges
    mbd::MemorySink memory;
    std::unique_ptr<mbd::OutputSink> csv = mbd::csv_output_format().make(dir / "r.csv");
    EXPECT_THROW(mbd::simulate(model, mbd::test::shared_registry(), s, {}, {&memory, csv.get()}), mbd::DynamicsError);
    EXPECT_FALSE(memory.complete());
    EXPECT_GE(memory.rows(), 1u);
    csv.reset();  // the run's end for the file: unfinished
    mbd::take_kept_output_notes();
    EXPECT_FALSE(fs::exists(dir / "r.csv"));
    EXPECT_EQ(read_text(dir / "r.csv.partial").find("t,"), 0u) << "the rows before the failure are kept";
}

// `simulate -o run.h5 --animation`: no CSV is written, so the frames can only come from the
// run's rows; the .glb and the .html are byte for byte what `mbd animate` makes from the CSV of
// the same run (17 digits: the CSV's values are the rows' values exactly).
TEST(AnimationSink, TheAnimationIsTheOneMadeFromTheCsvOfTheSameRun) {
    const fs::path dir = scratch("animation");
    const std::string scene = mbd::test::scene_path("bench/chain-5.yaml").string();
    const std::string run = "simulate " + scene + " --t-end 0.5 --output-step 0.01 -q ";
    for (const std::string format : {"glb", "html"}) {
        SCOPED_TRACE(format);
        const auto sink = run_mbd(run + "-o " + (dir / "r.h5").string() + " --animation " + (dir / ("sink." + format)).string());
        ASSERT_EQ(sink.exit_code, 0) << sink.err;
        ASSERT_EQ(run_mbd(run + "-o " + (dir / "r.csv").string()).exit_code, 0);
        const auto animate = run_mbd("animate " + scene + " " + (dir / "r.csv").string() + " -o " +
                                     (dir / ("csv." + format)).string());
        ASSERT_EQ(animate.exit_code, 0) << animate.err;
        const std::string a = read_text(dir / ("sink." + format)), b = read_text(dir / ("csv." + format));
        EXPECT_GT(a.size(), 1000u);
        EXPECT_TRUE(a == b) << "sizes " << a.size() << " and " << b.size();
        fs::remove(dir / "r.csv");
    }
}

}  // namespace
