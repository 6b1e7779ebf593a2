// The output contract (mbd/output_file.hpp), the stop-signal flag (mbd/interrupt.hpp),
// the output times (mbd/output_times.hpp) and the progress line (mbd/progress_bar.hpp),
// as library units: what a command relies on, checked without running one.
#include <mbd/csv.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_times.hpp>
#include <mbd/progress_bar.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::test::scratch;

// Any file's bytes: a FIFO's too (mbd::test::read_text takes regular files only).
std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(OutputFile, TheFinalNameAppearsOnlyOnCommit) {
    const fs::path dir = scratch("commit");
    const fs::path out = dir / "result.csv";
    {
        mbd::OutputFile file(out, "a,b\n");
        file.write_record("1,2\n");
        file.write_record("3,4\n");
        EXPECT_FALSE(fs::exists(out));
        EXPECT_TRUE(fs::exists(dir / "result.csv.partial"));
        file.commit();
    }
    EXPECT_EQ(read_text(out), "a,b\n1,2\n3,4\n");
    EXPECT_FALSE(fs::exists(dir / "result.csv.partial"));
    EXPECT_TRUE(mbd::take_kept_output_notes().empty());
}

TEST(OutputFile, AnAbandonedFileKeepsItsWholeRecordsInThePartialFile) {
    const fs::path dir = scratch("abandon");
    const fs::path out = dir / "result.csv";
    write_text(out, "an earlier complete result\n");
    mbd::take_kept_output_notes();
    {
        mbd::OutputFile file(out, "t,x\n");
        for (int k = 0; k < 5; ++k) file.write_record(std::to_string(k) + "," + std::to_string(k * k) + "\n");
        // destroyed without commit(): a failed or interrupted run
    }
    EXPECT_EQ(read_text(dir / "result.csv.partial"), "t,x\n0,0\n1,1\n2,4\n3,9\n4,16\n");
    EXPECT_EQ(read_text(out), "an earlier complete result\n") << "the final name is replaced only by a complete result";
    const std::vector<std::string> notes = mbd::take_kept_output_notes();
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_TRUE(contains(notes[0], (dir / "result.csv.partial").string())) << notes[0];
    EXPECT_TRUE(contains(notes[0], "was not written")) << notes[0];
}

TEST(OutputFile, NoRecordMeansNoFileLeftBehind) {
    const fs::path dir = scratch("empty");
    { mbd::OutputFile file(dir / "result.csv", "t,x\n"); }
    EXPECT_TRUE(fs::is_empty(dir));
    EXPECT_TRUE(mbd::take_kept_output_notes().empty());
}

// A device or FIFO (-o /dev/null, a pipe to another program) is written in place: there is no
// final name to complete, so no NAME.partial appears beside it, even when the run stops.
TEST(OutputFile, ADeviceOrPipeIsWrittenInPlace) {
    const fs::path dir = scratch("fifo");
    const fs::path fifo = dir / "rows";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = read_text(fifo); });
    {
        mbd::OutputFile file(fifo, "t,x\n");
        file.write_record("0,1\n");
        file.write_record("1,2\n");
        // destroyed without commit(): a stopped run
    }
    reader.join();
    EXPECT_EQ(received, "t,x\n0,1\n1,2\n");
    EXPECT_FALSE(fs::exists(dir / "rows.partial"));
    EXPECT_TRUE(mbd::take_kept_output_notes().empty());
    // (a /dev/null.partial left by an older build is not this test's to judge: only none is made)
    const bool stale = fs::exists("/dev/null.partial");
    const auto stale_time = stale ? fs::last_write_time("/dev/null.partial") : fs::file_time_type{};
    {
        mbd::OutputFile null("/dev/null", "t,x\n");
        null.write_record("0,1\n");
        null.commit();
    }
    EXPECT_EQ(fs::exists("/dev/null.partial"), stale);
    if (stale) EXPECT_EQ(fs::last_write_time("/dev/null.partial"), stale_time);
    EXPECT_TRUE(fs::exists("/dev/null"));
}

TEST(OutputFile, ReplaceKeepsOnlyTheLatestDocumentAndSaysWhatItHolds) {
    const fs::path dir = scratch("replace");
    mbd::take_kept_output_notes();
    {
        mbd::OutputFile file(dir / "matrix.md");
        file.replace("# one case\n", "the matrix of the first 1 of 3 cases");
        file.replace("# two cases\nsecond\n", "the matrix of the first 2 of 3 cases");
    }
    EXPECT_EQ(read_text(dir / "matrix.md.partial"), "# two cases\nsecond\n");
    const std::vector<std::string> notes = mbd::take_kept_output_notes();
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_TRUE(contains(notes[0], "the first 2 of 3 cases")) << notes[0];
}

TEST(OutputFile, ADocumentWrittenInPartsIsWholeOrAbsent) {
    const fs::path dir = scratch("document");
    mbd::take_kept_output_notes();
    const std::string big(300000, 'x');  // larger than one write block
    {
        mbd::OutputFile file(dir / "done.glb");
        mbd::DocumentStream out(file);
        out << "head:" << big << ":tail";
        out.flush();
        file.commit();
    }
    EXPECT_EQ(read_text(dir / "done.glb"), "head:" + big + ":tail");
    {  // stopped before commit (an error in the export): no file under either name, no note
        mbd::OutputFile file(dir / "stopped.glb");
        mbd::DocumentStream out(file);
        out << big << big;
    }
    EXPECT_FALSE(fs::exists(dir / "stopped.glb"));
    EXPECT_FALSE(fs::exists(dir / "stopped.glb.partial"));
    EXPECT_TRUE(mbd::take_kept_output_notes().empty());
    // a failed write throws the OutputError out of the stream operation, naming the file
    fs::create_symlink("/dev/full", dir / "full.glb.partial");
    try {
        mbd::OutputFile file(dir / "full.glb");
        mbd::DocumentStream out(file);
        out << big << big;
        out.flush();
        file.commit();
        FAIL() << "no error on a full device";
    } catch (const mbd::OutputError& e) {
        EXPECT_TRUE(contains(e.what(), "full.glb")) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "full.glb"));
}

// Two runs on one output (issue 42): the second refuses at its start, naming the first, and
// the first's records are untouched; once the first has ended the name is free again. A FIFO
// (a device's case) gets no lock file beside it.
TEST(OutputFile, ASecondWriterOfTheSameOutputRefusesWhileTheFirstRuns) {
    const fs::path dir = scratch("lock");
    const fs::path out = dir / "run.csv";
    {
        mbd::OutputFile first(out, "t,x\n");
        first.write_record("0,1\n");
        EXPECT_TRUE(fs::exists(dir / "run.csv.lock"));
        try {
            mbd::OutputFile second(out, "t,y\n");
            FAIL() << "the second writer was not refused";
        } catch (const mbd::InputError& e) {
            EXPECT_TRUE(contains(e.what(), "being written by another run")) << e.what();
            EXPECT_TRUE(contains(e.what(), "process " + std::to_string(::getpid()))) << e.what();
        }
        first.write_record("1,2\n");
        first.commit();
    }
    EXPECT_EQ(read_text(out), "t,x\n0,1\n1,2\n");
    EXPECT_FALSE(fs::exists(dir / "run.csv.lock"));
    {
        mbd::OutputFile again(out, "t,x\n");  // free once the first has ended
        again.write_record("0,3\n");
        again.commit();
    }
    EXPECT_EQ(read_text(out), "t,x\n0,3\n");
    const fs::path fifo = dir / "rows";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::thread reader([&] { read_text(fifo); });
    {
        mbd::OutputFile stream(fifo, "t,x\n");
        EXPECT_FALSE(fs::exists(dir / "rows.lock"));
        stream.commit();
    }
    reader.join();
}

TEST(OutputFile, AMissingFolderIsNamed) {
    const fs::path out = scratch("missing") / "no" / "such" / "folder" / "out.csv";
    try {
        mbd::OutputFile file(out);
        FAIL() << "no error";
    } catch (const mbd::OutputError& e) {
        EXPECT_TRUE(contains(e.what(), out.string())) << e.what();
    }
}

TEST(OutputFile, AFullFileSystemLeavesWholeRecordsOnly) {
    // /dev/full fails every write with ENOSPC: the CSV writer on a path whose
    // NAME.partial is /dev/full (a link) reports the path and the cause
    const fs::path dir = scratch("full");
    fs::create_symlink("/dev/full", dir / "out.csv.partial");
    mbd::take_kept_output_notes();
    try {
        mbd::CsvWriter writer((dir / "out.csv").string(), {"t", "x"});
        for (int k = 0; k < 100000; ++k) writer.row({0.001 * k, 1.0 / (k + 1)});
        writer.close();
        FAIL() << "no error on a full device";
    } catch (const mbd::OutputError& e) {
        EXPECT_TRUE(contains(e.what(), "out.csv")) << e.what();
        EXPECT_TRUE(contains(e.what(), "No space left on device")) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "out.csv"));
}

TEST(CheckOutputPath, RefusesTheInputByAnyPath) {
    const fs::path dir = scratch("inputs");
    const fs::path scene = dir / "scene.yaml", base = dir / "base.yaml";
    write_text(scene, "base: base.yaml\n");
    write_text(base, "dimension: planar\n");
    fs::create_symlink(scene, dir / "link.yaml");
    fs::create_hard_link(base, dir / "hard.yaml");
    fs::create_directories(dir / "sub");
    const std::vector<fs::path> inputs{scene, base};
    const std::vector<fs::path> same{scene,
                                     dir / "." / "scene.yaml",
                                     dir / "sub" / ".." / "scene.yaml",
                                     dir / "link.yaml",
                                     base,
                                     dir / "hard.yaml"};
    for (const fs::path& out : same) {
        try {
            mbd::check_output_path(out, inputs, "--output");
            ADD_FAILURE() << out << " accepted";
        } catch (const mbd::InputError& e) {
            EXPECT_TRUE(contains(e.what(), "--output")) << e.what();
            EXPECT_TRUE(contains(e.what(), "input file")) << e.what();
        }
    }
    // relative to the working directory
    const fs::path cwd = fs::current_path();
    fs::current_path(dir);
    EXPECT_THROW(mbd::check_output_path("./scene.yaml", inputs, "--output"), mbd::InputError);
    EXPECT_NO_THROW(mbd::check_output_path("./result.csv", inputs, "--output"));
    fs::current_path(cwd);
    // OUT.partial would be written over an input
    write_text(dir / "x.csv.partial", "an input that looks like a partial file\n");
    EXPECT_THROW(mbd::check_output_path(dir / "x.csv", {dir / "x.csv.partial"}, "--output"), mbd::InputError);
    // a folder, and a file in a missing folder
    EXPECT_THROW(mbd::check_output_path(dir / "sub", inputs, "--output"), mbd::InputError);
    EXPECT_THROW(mbd::check_output_path(dir / "nowhere" / "out.csv", inputs, "--output"), mbd::InputError);
    EXPECT_NO_THROW(mbd::check_output_path(dir / "out.csv", inputs, "--output"));
    EXPECT_EQ(read_text(scene), "base: base.yaml\n");
}

TEST(Interrupt, ASignalInAScopeBecomesAnInterruptedAtTheNextCheck) {
    {
        mbd::InterruptScope scope;
        EXPECT_EQ(mbd::pending_interrupt(), 0);
        EXPECT_NO_THROW(mbd::stop_if_interrupted(0.5));
        std::raise(SIGTERM);  // only sets the flag
        EXPECT_EQ(mbd::pending_interrupt(), SIGTERM);
        try {
            mbd::stop_if_interrupted(0.75);
            FAIL() << "no Interrupted";
        } catch (const mbd::Interrupted& e) {
            EXPECT_EQ(e.signal(), SIGTERM);
            EXPECT_EQ(e.exit_status(), 143);
            EXPECT_EQ(e.signal_name(), "SIGTERM");
            EXPECT_EQ(e.time(), 0.75);
        }
    }
    EXPECT_EQ(mbd::pending_interrupt(), 0) << "outside a scope nothing is pending";
    {
        mbd::InterruptScope fresh;
        std::raise(SIGINT);
        EXPECT_EQ(mbd::pending_interrupt(), SIGINT);
    }
    EXPECT_NO_THROW(mbd::stop_if_interrupted());
    EXPECT_EQ(mbd::Interrupted(SIGINT, 0.0).exit_status(), 130);
    EXPECT_EQ(mbd::Interrupted(SIGHUP, 0.0).exit_status(), 129);
}

TEST(OutputTimes, CountsIntervalsAndRefusesImpossibleSteps) {
    EXPECT_EQ(mbd::output_intervals(1.0, 0.1), 10);    // 1 / 0.1 is 10 up to round-off
    EXPECT_EQ(mbd::output_intervals(1.0, 0.3), 4);     // the last interval is shorter
    EXPECT_EQ(mbd::output_intervals(0.0, 0.1), 0);
    EXPECT_THROW(mbd::output_intervals(1.0, 1e-300, "--step"), mbd::InputError);
    EXPECT_THROW(mbd::output_intervals(1.0, 0.0, "--step"), mbd::InputError);
    EXPECT_THROW(mbd::output_intervals(NAN, 0.1), mbd::InputError);
    EXPECT_THROW(mbd::output_intervals(1.0, NAN), mbd::InputError);
    EXPECT_THROW(mbd::output_intervals(-1.0, 0.1), mbd::InputError);
    try {
        mbd::output_intervals(1.0, 1e-300, "--step");
    } catch (const mbd::InputError& e) {
        EXPECT_TRUE(contains(e.what(), "--step")) << e.what();
        EXPECT_TRUE(contains(e.what(), "rows")) << e.what();
    }
    EXPECT_EQ(mbd::output_intervals(1.0, 1.0 / (mbd::kMaxOutputRows - 1)), mbd::kMaxOutputRows - 1);
}

TEST(ProgressLine, ShowsElapsedTimeAndTimeLeftWithinTheWidth) {
    EXPECT_EQ(mbd::format_duration(7.2), "0:07");
    EXPECT_EQ(mbd::format_duration(62.0), "1:02");
    EXPECT_EQ(mbd::format_duration(3723.0), "1:02:03");
    EXPECT_EQ(mbd::format_duration(NAN), "--:--");
    // a quarter done after 10 s: 30 s left at the same rate
    const std::string line = mbd::progress_line(0.25, 10.0, "t = 2.5 / 10 s", 200);
    EXPECT_TRUE(contains(line, " 25%")) << line;
    EXPECT_TRUE(contains(line, "0:10 elapsed")) << line;
    EXPECT_TRUE(contains(line, "0:30 left")) << line;
    EXPECT_TRUE(contains(line, "t = 2.5 / 10 s")) << line;
    // never wider than the terminal (less one column), whatever the detail
    for (int width : {20, 40, 80})
        EXPECT_LT(mbd::progress_line(0.5, 1.0, std::string(300, 'x'), width).size(), static_cast<size_t>(width));
    EXPECT_TRUE(contains(mbd::progress_line(0.0, 1.0, "", 80), "--:-- left"));
}

}  // namespace
