#!/usr/bin/env python3
"""Docs as tests (issue 41): run every command block of README.md and docs/*.md.

Every fenced block in ```sh, ```bash, ```console or ```python is run, in a working folder that
holds copies of scenes/, examples/ and docs/ (so a command that writes docs/stability.md writes
the copy) and links to the rest of the source tree, with the build's `mbd` first on PATH and the
build's Python package on PYTHONPATH. Blocks of one markdown file run in order in one folder, so a
block may use the files an earlier block of the same page wrote (a result CSV, say).

- ```sh / ```bash: one bash script (`set -eo pipefail`): every command must succeed.
- ```console: `$ COMMAND` lines, each followed by its documented output. Each command must exit 0
  (a doc that shows a failure says so with `; echo "exit status $?"`), and the lines shown must
  appear in its output (stdout and stderr) in that order. `...` in a line stands for any text,
  a run of spaces for any run of spaces;
  a number matches the output's number rounded to the digits shown (1.2e-06 matches
  1.2345e-06, 0.722 matches 0.72249).
- ```python: run as a program with `python3` (Debian's) when it is complete (it imports what it
  uses); its ```text block right after, if any, is its expected output (as for console).
- A ```text block right after a sh block is that block's expected output.
- Every `--option` in an inline `mbd COMMAND ...` span of the prose must be an option of that
  command (`mbd COMMAND --help`).

An HTML comment on the line before a block marks what it needs:
- `<!-- doc-test: needs mpi -->`: runs under OpenMPI (mpirun on PATH, as root allowed); the test
  fails when mpirun is missing (scripts/install-deps.sh installs it).
- `<!-- doc-test: needs peers -->`: needs the Simbody and MuJoCo peer programs (build/bin/peers);
  fails when they were not built.
- `<!-- doc-test: run-by SCRIPT ... -->`: the block is what a CI script or another test's script
  runs (building, installing, the sanitizer and fuzz runs): it is not run again here (a build
  inside the test would rebuild the tree it tests), but each of its commands (split at `&&`,
  comments dropped) must be in a command of one of the named scripts (a shell variable there
  stands for any word), so the doc cannot drift from what CI does. These are listed in the
  report, as are the README's two set-up commands (scripts/example.sh, scripts/test.sh), which
  are this test's caller.
"""

import argparse
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

RUN_LANGUAGES = {"sh", "bash", "console", "python"}
MARKER = re.compile(r"<!--\s*doc-test:\s*(.*?)\s*-->")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
# The README's set-up commands call the build and the whole suite, this test included.
CALLERS = {"bash scripts/example.sh", "bash scripts/test.sh"}


class Block:
    def __init__(self, path, line, language, text, marker):
        self.path, self.line, self.language, self.text, self.marker = path, line, language, text, marker
        self.expected = None  # the lines of a ```text block that follows

    def where(self):
        return f"{self.path}:{self.line}"


def parse_blocks(path, relative):
    """The fenced blocks of a markdown file, with their markers and following ```text blocks."""
    lines = pathlib.Path(path).read_text().splitlines()
    blocks, k, previous = [], 0, None
    while k < len(lines):
        fence = re.match(r"^```(\w*)\s*$", lines[k])
        if not fence:
            if lines[k].strip():
                previous = None if not MARKER.search(lines[k]) else previous
            k += 1
            continue
        language, start = fence.group(1), k
        marker_line = lines[k - 1] if k > 0 else ""
        marker = MARKER.search(marker_line)
        k += 1
        body = []
        while k < len(lines) and lines[k].rstrip() != "```":
            body.append(lines[k])
            k += 1
        k += 1
        if language == "text" and previous is not None and previous.expected is None:
            previous.expected = body
            previous = None
            continue
        if language in RUN_LANGUAGES:
            block = Block(relative, start + 1, language, "\n".join(body) + "\n", marker.group(1) if marker else "")
            blocks.append(block)
            previous = block
        else:
            previous = None
    return blocks


def number_matches(shown, actual):
    """`actual` rounded to the digits of `shown` is `shown`."""
    try:
        value = float(actual)
    except ValueError:
        return False
    if re.search(r"[eE]", shown):
        mantissa = shown.lower().split("e")[0]
        decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
        formatted = f"{value:.{decimals}e}"
        return float(formatted) == float(shown)
    decimals = len(shown.split(".")[1]) if "." in shown else 0
    return abs(value - float(shown)) <= 0.5 * 10.0 ** (-decimals) * (1 + 1e-9)


def number_pattern(shown):
    """A regex for the output's number that a shown number stands for: its digits but the last
    (which rounding may change) and any further digits; number_matches then checks the rounding
    (a carry into the leading digits, 1.9999 shown as 2.000, is not found: show a digit less).
    Pinning the leading digits keeps `...` from skipping to another number of the line."""
    mantissa, _, exponent = shown.lower().partition("e")
    lead = mantissa[:-1]
    more = r"\d*" if re.search(r"\d", lead) else r"\d+"  # at least one digit
    body = re.escape(lead) + more + (r"(?:\.\d*)?" if "." not in lead else "")
    if exponent:
        body += r"[eE][-+]?\d+"
    return r"(?<![\d.])(" + body + r")(?![\d.])"


def line_pattern(expected):
    """A regex for one expected line: literal text, `...` as any text, numbers captured."""
    def literal(text):  # a run of spaces stands for any run (columns are aligned with spaces)
        return r"\s+".join(re.escape(piece) for piece in re.split(r"\s+", text))

    pattern, numbers, position = "", [], 0
    for token in re.finditer(r"\.\.\.|" + NUMBER.pattern, expected):
        pattern += literal(expected[position:token.start()])
        if token.group(0) == "...":
            pattern += ".*?"
        else:
            pattern += number_pattern(token.group(0))
            numbers.append(token.group(0))
        position = token.end()
    pattern += literal(expected[position:])
    return re.compile(pattern), numbers


def check_output(expected_lines, output):
    """The expected lines appear in the output in order; returns the first missing one."""
    actual = output.splitlines()
    at = 0
    for expected in (e.rstrip() for e in expected_lines):
        if not expected.strip():
            continue
        pattern, numbers = line_pattern(expected.strip())
        found = False
        while at < len(actual):
            match = pattern.search(actual[at])
            at += 1
            if match and all(number_matches(s, a) for s, a in zip(numbers, match.groups())):
                found = True
                break
        if not found:
            return expected
    return None


def console_commands(text):
    """The (command, expected output lines) pairs of a console block."""
    pairs = []
    for line in text.splitlines():
        if line.startswith("$ "):
            pairs.append([line[2:], []])
        elif pairs:
            if pairs[-1][1] == [] and pairs[-1][0].endswith("\\"):
                pairs[-1][0] = pairs[-1][0][:-1] + line
            else:
                pairs[-1][1].append(line)
    return pairs


def command_parts(text):
    """The commands of a block: continuation lines joined, comments dropped, split at &&."""
    parts = []
    for line in text.replace("\\\n", " ").splitlines():
        line = re.sub(r"(^|\s)#.*$", "", line).strip()
        if line:
            parts.extend(p.strip() for p in line.split("&&") if p.strip())
    return parts


def words(command):
    try:
        return shlex.split(command)
    except ValueError:
        return command.split()


def script_commands(path):
    """The commands of a script as lists of words (split at `&&`, comments dropped)."""
    return [words(part) for part in command_parts(path.read_text())]


def runs(script_command, doc_words):
    """The doc's command is in the script's command: its words in a row (a wrapper such as
    `run_phase NAME` may come before them, options and redirections after), where a word of the
    script with a shell variable ($x, ${x}) stands for any word."""
    for start in range(len(script_command) - len(doc_words) + 1):
        if all(s == d or "$" in s for s, d in zip(script_command[start:], doc_words)):
            return True
    return False


def check_run_by(block, source):
    """Each command of a run-by block begins a command of one of the named scripts."""
    names = block.marker.split()[1:]
    commands = []
    for name in names:
        path = source / name
        if not path.is_file():
            return f"run-by names '{name}', which is not a file of the source tree"
        commands.extend(script_commands(path))
    for part in command_parts(block.text):
        if part in CALLERS:
            continue
        if not any(runs(c, words(part)) for c in commands):
            return f"'{part}' is not a command of {', '.join(names)}"
    return None


def environment(args, work):
    env = dict(os.environ)
    env["PATH"] = f"{args.bin}:{env.get('PATH', '')}"
    env["PYTHONPATH"] = args.pythonpath
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    env["OMPI_MCA_rmaps_base_oversubscribe"] = "1"
    env["MPLBACKEND"] = "Agg"
    env["HOME"] = str(work)
    return env


def run(command, work, env, timeout, language="sh"):
    if language == "python":
        argv = ["/usr/bin/python3", "-c", command]
    elif language == "console":  # one command line, as typed: `a; echo $?` must reach the echo
        argv = ["bash", "-c", command]
    else:
        argv = ["bash", "-c", "set -eo pipefail\n" + command]
    start = time.monotonic()
    done = subprocess.run(argv, cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout, stdin=subprocess.DEVNULL)
    return done.returncode, done.stdout, time.monotonic() - start


def make_workspace(source, build, work):
    shared = source.parent / "shared"  # the models beside the tree (docs/import.md)
    if shared.is_dir():
        (work.parent / "shared").symlink_to(shared)
    for name in ("scenes", "examples", "docs"):
        shutil.copytree(source / name, work / name, symlinks=True)
    for entry in source.iterdir():
        if entry.name not in ("scenes", "examples", "docs", "build") and not entry.name.startswith("."):
            (work / entry.name).symlink_to(entry)
    (work / "build").symlink_to(build)


def needs_check(block, args):
    marker = block.marker
    if marker == "needs mpi" and shutil.which("mpirun") is None:
        return "needs mpirun (Debian openmpi-bin, scripts/install-deps.sh), which is not on PATH"
    if marker == "needs peers":
        peers = pathlib.Path(args.build) / "bin" / "peers"
        if not (peers / "mbd_peer_simbody").exists() or not (peers / "mbd_peer_mujoco").exists():
            return f"needs the peer programs in {peers}, which were not built"
    if marker and marker not in ("needs mpi", "needs peers") and not marker.startswith("run-by "):
        return f"unknown doc-test marker '{marker}'"
    return None


def run_block(block, work, env, timeout):
    """None when the block runs and its documented outcome holds, else the failure."""
    if block.language == "console":
        for command, expected in console_commands(block.text):
            status, output, _ = run(command, work, env, timeout, "console")
            if status != 0:
                return f"`{command}` exited {status}:\n{output[-3000:]}"
            missing = check_output(expected, output)
            if missing is not None:
                return f"`{command}`: the documented line\n    {missing}\nis not in its output:\n{output[-3000:]}"
        return None
    status, output, _ = run(block.text, work, env, timeout, block.language)
    if status != 0:
        return f"exited {status}:\n{output[-3000:]}"
    if block.expected is not None:
        missing = check_output(block.expected, output)
        if missing is not None:
            return f"the documented line\n    {missing}\nis not in its output:\n{output[-3000:]}"
    return None


def inline_option_problems(pages, source, env):
    """Each `--option` of an inline `mbd COMMAND ...` span of the prose is an option of that
    command (`mbd COMMAND --help`): a renamed or removed option cannot linger in a sentence."""
    listing = subprocess.run(["mbd", "--help"], env=env, capture_output=True, text=True).stdout
    commands = set(re.findall(r"^  ([a-z]+) ", listing, re.M))
    helps, problems = {}, []
    for page in pages:
        text = page.read_text()
        for span in re.finditer(r"`(mbd (plugin check|[a-z]+)\b[^`]*)`", text):
            command = span.group(2)
            if command.split()[0] not in commands:
                continue  # a command named as not there yet (`mbd export`)
            if command not in helps:
                helps[command] = subprocess.run(["mbd", *command.split(), "--help"], env=env,
                                                capture_output=True, text=True).stdout
            for option in re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", span.group(1)):
                if not re.search(r"(^|[\s,])" + re.escape(option) + r"\b", helps[command]):
                    line = text.count("\n", 0, span.start()) + 1
                    problems.append(f"{page.relative_to(source)}:{line}: `{span.group(1)}`: "
                                    f"{option} is not an option of `mbd {command}`")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("--only", default="", help="only the markdown files whose path contains this")
    parser.add_argument("--timeout", type=float, default=120)
    args = parser.parse_args()
    source, build = pathlib.Path(args.source).resolve(), pathlib.Path(args.build).resolve()
    args.bin, args.pythonpath = str(build / "bin"), str(build / "python")

    pages = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    failures, report, total_start = [], [], time.monotonic()
    for page in pages:
        relative = str(page.relative_to(source))
        if args.only and args.only not in relative:
            continue
        blocks = parse_blocks(page, relative)
        if not blocks:
            continue
        with tempfile.TemporaryDirectory(prefix="mbd-docs-") as folder:
            work = pathlib.Path(folder) / "mbd"
            work.mkdir()
            make_workspace(source, build, work)
            env = environment(args, work)
            for block in blocks:
                start = time.monotonic()
                problem = needs_check(block, args)
                if problem is None and block.marker.startswith("run-by "):
                    problem = check_run_by(block, source)
                    outcome = "run by " + " ".join(block.marker.split()[1:])
                elif problem is None:
                    try:
                        problem = run_block(block, work, env, args.timeout)
                    except subprocess.TimeoutExpired:
                        problem = f"did not end within {args.timeout} s"
                    outcome = "ran" + (f" ({block.marker})" if block.marker else "")
                took = time.monotonic() - start
                if problem is not None:
                    failures.append(f"{block.where()} ({block.language}): {problem}")
                    outcome = "FAILED"
                report.append(f"{block.where():28s} {block.language:8s} {took:6.1f} s  {outcome}")
    inline = inline_option_problems(pages, source, environment(args, source))
    failures.extend(inline)
    report.append(f"inline `mbd COMMAND --option` spans of the prose: {len(inline)} unknown options")
    print("\n".join(report))
    print(f"callers, not run here: {', '.join(sorted(CALLERS))} (README.md; they run this test)")
    print(f"{len(report)} blocks in {time.monotonic() - total_start:.1f} s, {len(failures)} failed")
    for failure in failures:
        print("\nFAILED " + failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
