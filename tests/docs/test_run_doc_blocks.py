"""The docs runner's own checks (tests/docs/run_doc_blocks.py): a doc whose output drifts must
fail, a block of CI commands that CI does not run must fail, and the markdown parser must find
the blocks, their markers and their expected output."""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import run_doc_blocks as runner  # noqa: E402


def test_a_number_matches_to_the_digits_shown_and_no_further():
    assert runner.number_matches("1.2e-06", "1.2345e-06")
    assert not runner.number_matches("1.2e-06", "1.26e-06")
    assert runner.number_matches("0.722", "0.72249")
    assert not runner.number_matches("0.722", "0.7226")
    assert runner.number_matches("1.4473083517", "1.4473083516526217")
    assert not runner.number_matches("1.4473083516", "1.4473083516526217")  # 5.3e-11 > half a digit
    assert not runner.number_matches("3", "nan")


def test_expected_lines_must_appear_in_order_with_their_numbers():
    output = "wrote 3 rows\nt,x\n0,1.5\n0.5,2.25\n"
    assert runner.check_output(["t,x", "0,1.5", "0.5,2.25"], output) is None
    assert runner.check_output(["wrote ... rows", "0.5,2.1"], output) == "0.5,2.1"
    assert runner.check_output(["0,1.5"], "10,1.5\n") == "0,1.5"  # a number is matched whole
    assert runner.check_output(["0.5,2.25", "0,1.5"], output) == "0,1.5"  # order
    assert runner.check_output(["t,y"], output) == "t,y"


def test_console_commands_and_their_outputs():
    pairs = runner.console_commands("$ mbd check a.yaml; echo \"exit status $?\"\nmbd: error: x\nexit status 2\n$ ls\n")
    assert pairs == [['mbd check a.yaml; echo "exit status $?"', ["mbd: error: x", "exit status 2"]], ["ls", []]]


def test_a_ci_block_must_be_what_the_script_runs(tmp_path):
    (tmp_path / "ci.sh").write_text('run_phase tests bash scripts/test.sh\ncmake --install "$dir" --prefix "$p" >/dev/null\n')
    block = runner.Block("X.md", 1, "sh", "", "run-by ci.sh")
    block.text = "bash scripts/test.sh\ncmake --install build --prefix /usr/local   # comment\n"
    assert runner.check_run_by(block, tmp_path) is None
    block.text = "cmake --install build --prefix /usr/local --strip\n"
    assert "is not a command" in runner.check_run_by(block, tmp_path)
    block.text = "bash scripts/other.sh\n"
    assert "is not a command" in runner.check_run_by(block, tmp_path)
    block.marker = "run-by missing.sh"
    assert "not a file" in runner.check_run_by(block, tmp_path)


def test_blocks_markers_and_following_text(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("intro\n<!-- doc-test: needs mpi -->\n```sh\nmpirun x\n```\n\n```text\nout\n```\n"
                    "```yaml\na: 1\n```\n```python\nprint(1)\n```\nprose\n```text\nnot its output\n```\n")
    blocks = runner.parse_blocks(page, "p.md")
    assert [(b.language, b.marker, b.expected) for b in blocks] == [
        ("sh", "needs mpi", ["out"]), ("python", "", None)]


def test_an_unknown_marker_is_refused():
    block = runner.Block("X.md", 1, "sh", "true\n", "skip because")
    assert "unknown doc-test marker" in runner.needs_check(block, None)


def test_an_inline_option_the_command_lacks_is_found(tmp_path):
    fake = tmp_path / "bin" / "mbd"  # an mbd whose simulate takes --t-end only
    fake.parent.mkdir()
    fake.write_text('#!/bin/sh\nif [ "$1" = --help ]; then echo "Subcommands:"; echo "  simulate    Forward dynamics"; '
                    'else echo "  --t-end FLOAT  end time"; fi\n')
    fake.chmod(0o755)
    page = tmp_path / "p.md"
    page.write_text("run `mbd simulate --t-end 1 --bogus`;\n`mbd export --x` is not there yet\n")
    env = {"PATH": f"{fake.parent}:/usr/bin:/bin"}
    assert runner.inline_option_problems([page], tmp_path, env) == [
        "p.md:1: `mbd simulate --t-end 1 --bogus`: --bogus is not an option of `mbd simulate`"]


def test_a_wildcard_does_not_skip_to_another_number_of_the_line():
    line = "     2  real           -0.32286643           +0i      0.322866429    0.051385788            1"
    assert runner.check_output(["2  real ... -0.32286643 ..."], line) is None
    assert runner.check_output(["2  real ... -0.3228664 ..."], line) is None
    assert runner.check_output(["2  real ... -0.32286649 ..."], line) == "2  real ... -0.32286649 ..."
    assert runner.check_output(["3  real ..."], line) == "3  real ..."
    assert runner.check_output(["exit status 2"], "exit status 2\n") is None
    assert runner.check_output(["exit status 2"], "exit status \n") == "exit status 2"
