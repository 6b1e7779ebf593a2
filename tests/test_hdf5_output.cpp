// `mbd simulate --output run.h5` (issue 41, item 3; docs/user-guide.md "Result files"): the
// HDF5 sink writes the CSV's rows value for value in a third of its size or less. The HDF5
// file is read here with the HDF5 C API directly and the CSV with std::stod, each independently
// of the writers, and every value of one is compared bit for bit with the other's.
#include <gtest/gtest.h>

#include <csignal>
#include <chrono>
#include <thread>

#include <hdf5.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/child_process.hpp"
#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::run_mbd;
using mbd::test::scratch;
using mbd::test::write_text;

// The planar chain of scripts/gen_bench_scenes.py (chain-N): links of 0.1 m and 1 kg hanging
// from the ground by revolute joints, released from the straight horizontal configuration.
std::string chain_scene(int links) {
    const double L = 0.1;
    std::ostringstream s;
    s << "name: chain-" << links << "\ndimension: planar\ngravity: [0, -9.81]\nbodies:\n";
    for (int k = 0; k < links; ++k)
        s << "  - {name: l" << k << ", mass: 1.0, inertia: " << mbd::test::g17(L * L / 12)
          << ", position: [" << mbd::test::g17(L * k + L / 2) << ", 0.0]}\n";
    s << "joints:\n";
    for (int k = 0; k < links; ++k)
        s << "  - {name: j" << k << ", type: revolute, bodies: [" << (k == 0 ? std::string("ground") : "l" + std::to_string(k - 1))
          << ", l" << k << "], point: [" << mbd::test::g17(L * k) << ", 0.0]}\n";
    return s.str();
}

struct Table {
    std::vector<std::string> columns;
    std::vector<double> values;  // row-major
};

// The CSV through the tests' reader (std::stod: 17 digits read back exactly), row-major.
Table read_csv_exactly(const fs::path& file) {
    const mbd::test::Csv csv = mbd::test::read_csv(file);
    Table t{csv.header, {}};
    for (const auto& row : csv.rows) t.values.insert(t.values.end(), row.begin(), row.end());
    return t;
}

long long h5_long_attribute(hid_t object, const char* name) {
    long long value = -1;
    const hid_t a = H5Aopen(object, name, H5P_DEFAULT);
    EXPECT_GE(a, 0) << "no attribute " << name;
    if (a >= 0) {
        H5Aread(a, H5T_NATIVE_LLONG, &value);
        H5Aclose(a);
    }
    return value;
}

// /rows of the HDF5 file and the names in /columns; checks the root's `rows` and `complete`.
Table read_h5(const fs::path& file) {
    Table t;
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    EXPECT_GE(f, 0) << "cannot open " << file;
    if (f < 0) return t;
    const hid_t set = H5Dopen2(f, "rows", H5P_DEFAULT);
    const hid_t space = H5Dget_space(set);
    hsize_t dims[2] = {0, 0};
    EXPECT_EQ(H5Sget_simple_extent_ndims(space), 2);
    H5Sget_simple_extent_dims(space, dims, nullptr);
    t.values.resize(dims[0] * dims[1]);
    EXPECT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.values.data()), 0);
    const hid_t names_set = H5Dopen2(f, "columns", H5P_DEFAULT);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);  // as written: HDF5 converts no string between character sets
    std::vector<char*> names(dims[1], nullptr);
    EXPECT_GE(H5Dread(names_set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, names.data()), 0);
    for (char* n : names) t.columns.emplace_back(n ? n : "");
    const hid_t names_space = H5Dget_space(names_set);
    H5Dvlen_reclaim(type, names_space, H5P_DEFAULT, names.data());
    EXPECT_EQ(h5_long_attribute(f, "rows"), static_cast<long long>(dims[0]));
    EXPECT_EQ(h5_long_attribute(f, "complete"), 1);
    H5Sclose(names_space);
    H5Tclose(type);
    H5Dclose(names_set);
    H5Sclose(space);
    H5Dclose(set);
    H5Fclose(f);
    return t;
}

// Every value of `b` has the bits of the same value of `a`; returns the count of values.
std::size_t expect_bit_equal(const Table& a, const Table& b) {
    EXPECT_EQ(a.columns, b.columns);
    EXPECT_EQ(a.values.size(), b.values.size());
    std::size_t differing = 0;
    for (std::size_t k = 0; k < std::min(a.values.size(), b.values.size()); ++k)
        if (std::memcmp(&a.values[k], &b.values[k], sizeof(double)) != 0 && differing++ < 5)
            ADD_FAILURE() << "value " << k << " (row " << k / a.columns.size() << ", column "
                          << a.columns[k % a.columns.size()] << "): " << a.values[k] << " against " << b.values[k];
    EXPECT_EQ(differing, 0u);
    return a.values.size();
}

// chain-2000 (12,001 columns) for 0.005 s, a row every 5e-5 s: 101 rows, each value compared.
// (The 1 s run, 1,001 rows, takes minutes and writes 270 MB of CSV: measured by hand,
// its numbers are in docs/user-guide.md.)
TEST(Hdf5Output, Chain2000IsAThirdOfTheCsvAndHoldsTheSameNumbersBitForBit) {
    const fs::path dir = scratch("chain-2000");
    const fs::path scene = write_text(dir / "chain-2000.yaml", chain_scene(2000));
    const std::string run = "simulate " + scene.string() + " --t-end 0.005 --output-step 5e-5 -q --formulation embedding ";
    const auto csv = run_mbd(run + "--output " + (dir / "x.csv").string());
    ASSERT_EQ(csv.exit_code, 0) << csv.err;
    const auto h5 = run_mbd(run + "--output " + (dir / "x.h5").string());
    ASSERT_EQ(h5.exit_code, 0) << h5.err;
    EXPECT_FALSE(fs::exists(dir / "x.h5.partial"));
    EXPECT_FALSE(fs::exists(dir / "x.h5.lock"));

    const auto csv_bytes = fs::file_size(dir / "x.csv"), h5_bytes = fs::file_size(dir / "x.h5");
    RecordProperty("csv_bytes", std::to_string(csv_bytes));
    RecordProperty("h5_bytes", std::to_string(h5_bytes));
    std::printf("chain-2000, 101 rows: CSV %ju bytes, HDF5 %ju bytes (%.3f of the CSV)\n",
                static_cast<std::uintmax_t>(csv_bytes), static_cast<std::uintmax_t>(h5_bytes),
                static_cast<double>(h5_bytes) / static_cast<double>(csv_bytes));
    EXPECT_LE(3 * h5_bytes, csv_bytes);

    const Table a = read_csv_exactly(dir / "x.csv"), b = read_h5(dir / "x.h5");
    ASSERT_EQ(a.columns.size(), 1u + 2000u * 6u);
    EXPECT_EQ(a.values.size(), 101u * a.columns.size());
    expect_bit_equal(a, b);
    fs::remove_all(dir);  // 34 MB of results
}

// Reactions and diagnostics too, a run of several bands of rows (the band's last rows and a
// short last band), and the file read back the same way.
TEST(Hdf5Output, ReactionsAndDiagnosticsOverManyBandsAreTheCsvs) {
    const fs::path dir = scratch("pendulum");
    const std::string run = "simulate " + mbd::test::scene_path("dynamics/four-bar-conservative.yaml").string() +
                            " --t-end 2 --output-step 1e-4 --reactions --diagnostics -q ";
    ASSERT_EQ(run_mbd(run + "-o " + (dir / "x.csv").string()).exit_code, 0);
    const auto h5 = run_mbd(run + "-o " + (dir / "x.h5").string());
    ASSERT_EQ(h5.exit_code, 0) << h5.err;
    const Table a = read_csv_exactly(dir / "x.csv"), b = read_h5(dir / "x.h5");
    EXPECT_EQ(a.values.size(), 20001u * a.columns.size());
    EXPECT_NE(std::find(a.columns.begin(), a.columns.end(), "kinetic_energy"), a.columns.end());
    expect_bit_equal(a, b);
}

// The contact table of `--contacts` (contact_output.hpp) in HDF5 holds the CSV's numbers: a
// ball, a brick and a capsule falling onto a plane and onto each other, a row per contact.
TEST(Hdf5Output, TheContactTableIsTheCsvs) {
    const fs::path dir = scratch("contacts");
    const std::string run = "simulate " + mbd::test::scene_path("examples/force-collision-contact.yaml").string() +
                            " --integrator dopri5 --tol 1e-8 --t-end 1 --output-step 0.01 -q ";
    ASSERT_EQ(run_mbd(run + "-o " + (dir / "a.csv").string() + " --contacts " + (dir / "c.csv").string()).exit_code, 0);
    const auto h5 = run_mbd(run + "-o " + (dir / "b.csv").string() + " --contacts " + (dir / "c.h5").string());
    ASSERT_EQ(h5.exit_code, 0) << h5.err;
    const Table a = read_csv_exactly(dir / "c.csv"), b = read_h5(dir / "c.h5");
    ASSERT_EQ(a.columns.size(), 17u);
    EXPECT_GT(a.values.size(), 17u * 101u) << "more contacts than output rows: bodies rest on several points";
    expect_bit_equal(a, b);
}

// `mbd ARGUMENTS` started in a child process (its output to /dev/null).
// The peak resident memory (kB) of `mbd ARGUMENTS`, run to its end.
long mbd_peak_kb(const std::string& arguments) {
    return mbd::test::wait_peak_kb(mbd::test::spawn_quiet(mbd::test::mbd_command(MBD_EXECUTABLE, arguments)), 0, arguments);
}

// Rows stream to the file in bands: 400,001 rows of 13 values (42 MB of doubles) take no more
// memory than 4,001 rows.
TEST(Hdf5Output, MemoryDoesNotGrowWithTheRows) {
    const fs::path dir = scratch("memory");
    const std::string run = "simulate " + mbd::test::scene_path("dynamics/pendulum-a01.yaml").string() +
                            " --output-step 1e-5 -q --output " + (dir / "x.h5").string();
    const long short_run = mbd_peak_kb(run + " --t-end 0.04");
    const long long_run = mbd_peak_kb(run + " --t-end 4");
    RecordProperty("peak_kb_4001_rows", static_cast<int>(short_run));
    RecordProperty("peak_kb_400001_rows", static_cast<int>(long_run));
    std::printf("peak memory: %ld kB for 4,001 rows, %ld kB for 400,001 rows\n", short_run, long_run);
    EXPECT_LT(long_run - short_run, 16 * 1024) << "the rows (42 MB) were held in memory";
}

// While a run writes x.h5 it holds x.h5.lock: a second run on it is refused at its start; the
// first, stopped by SIGINT, leaves no file under either name (and no lock).
TEST(Hdf5Output, ASecondRunIsRefusedAndAStoppedRunLeavesNoFile) {
    const fs::path dir = scratch("lock");
    const std::string run = "simulate " + mbd::test::scene_path("dynamics/pendulum-a01.yaml").string() +
                            " --t-end 400 --output-step 1e-4 -q --output " + (dir / "x.h5").string();
    const pid_t first = mbd::test::spawn_quiet(std::string(MBD_EXECUTABLE) + " " + run);
    EXPECT_TRUE(mbd::test::wait_until([&] { return fs::exists(dir / "x.h5.partial"); }, first))
        << "the first run did not start writing";
    const auto second = run_mbd(run);
    EXPECT_EQ(second.exit_code, 2) << second.err;
    EXPECT_NE(second.err.find("is being written by another run"), std::string::npos) << second.err;
    kill(first, SIGINT);
    int status = 0;
    EXPECT_EQ(waitpid(first, &status, 0), first);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << "status " << status;
    EXPECT_FALSE(fs::exists(dir / "x.h5"));
    EXPECT_FALSE(fs::exists(dir / "x.h5.partial"));
    EXPECT_FALSE(fs::exists(dir / "x.h5.lock"));
}

TEST(Hdf5Output, AnUnknownExtensionIsRefusedNamingTheKnownOnes) {
    const fs::path dir = scratch("bad-extension");
    const std::string scene = mbd::test::scene_path("dynamics/pendulum-a01.yaml").string();
    for (const std::string name : {"x.txt", "x"}) {
        const auto r = run_mbd("simulate " + scene + " --t-end 0.1 -q --output " + (dir / name).string());
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find((dir / name).string() + ": --output: the format is chosen by the file's extension"),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find(".csv (CSV text), .h5 (HDF5)"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / name));
        EXPECT_FALSE(fs::exists(dir / (name + ".partial")));
    }
}

// A run that fails leaves no HDF5 file under either name (a part of one is no file to trust).
TEST(Hdf5Output, AFailedRunLeavesNoFile) {
    const fs::path dir = scratch("failed");
    // a fixed step far too large for the pendulum's rk4: the motion diverges
    const auto r = run_mbd("simulate " + mbd::test::scene_path("dynamics/pendulum-a01.yaml").string() +
                           " --t-end 200 --integrator rk4 --step 2 -q --output " + (dir / "x.h5").string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.h5"));
    EXPECT_FALSE(fs::exists(dir / "x.h5.partial"));
    EXPECT_FALSE(fs::exists(dir / "x.h5.lock"));
}

}  // namespace
