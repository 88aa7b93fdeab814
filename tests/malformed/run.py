#!/usr/bin/env python3
"""Runs the malformed-input corpus (tests/malformed/cases.json) through cwe.

Every case is one bad input and the cwe command line that reads it. A case passes when cwe
exits with the expected status (2), the first line of its error stream is the expected one
(absolute paths of the corpus, of tests/data/fuzz-findings and of the case's scratch output
folder written as {dir}, {fuzz} and {out}), nothing was written to the output folder (it stays
as the case set it up: empty, absent or its given files) and cwe ended within the timeout.

Cases marked "known_failure" (cwe does not keep the promise for them yet) are run too and
reported as XFAIL while cwe answers as it did when they were marked ("seen": "[exit status]
first line"). One whose answer changed to exit 2 with a first line of the promised form and
nothing written is reported as XPASS, to be reviewed: if the new line is right, remove
"known_failure" and "seen" and run --update. XPASS fails the run only with --strict.

    tests/malformed/run.py build/cwe                 # all cases
    tests/malformed/run.py build/cwe -k stl/         # the cases whose name contains "stl/"
    tests/malformed/run.py build/cwe --update        # rewrite the expected lines from cwe's

Standard library only. Exit status 0 when every case passes, 1 otherwise.
"""

import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

# Inputs that other inputs name (a FreeCAD library's tool bits), not cases of their own.
HELPERS = (".fctb",)
HERE = os.path.dirname(os.path.abspath(__file__))
MANIFEST = os.path.join(HERE, "cases.json")
FUZZ = os.path.normpath(os.path.join(HERE, "..", "data", "fuzz-findings"))

# The promised form of an error's first line: "source:line:col: error: …", "source:line: error:
# …" (an error that names a line) or "source: error: …" (a file as a whole, an option such as
# "--resolution", a job-file key such as 'job.json: "resolution"', or "cwe" for the command line
# itself).
PROMISED = re.compile(r"^(?!cwe: internal error)(?!error:)\S.*?(:\d+(:\d+)?)?: error: \S")
NOT_PROMISED = ("(this is a bug in cwe)", "internal error", "terminate called", "Could not convert",
                "The following argument", "std::", "what():")


def promised_form(line):
    return bool(PROMISED.match(line)) and not any(s in line for s in NOT_PROMISED)


def load_manifest():
    with open(MANIFEST, encoding="utf-8") as f:
        return json.load(f)


def case_name(case):
    if "name" in case:
        return case["name"]
    return os.path.splitext(case["input"])[0]


def case_kind(case):
    if "kind" in case:
        return case["kind"]
    return case["input"].split("/")[0]


def input_path(case):
    text = case.get("input", "")
    if text.startswith("{fuzz}/"):
        return os.path.join(FUZZ, text[len("{fuzz}/"):])
    return os.path.join(HERE, text)


def expand(arg, case, out):
    return (arg.replace("{input}", input_path(case) if "input" in case else "")
            .replace("{arg}", case.get("arg", "")).replace("{dir}", HERE)
            .replace("{fuzz}", FUZZ).replace("{out}", out))


def case_args(case, commands):
    """The case's command line: its own "args", else its kind's in "commands"."""
    return case["args"] if "args" in case else commands[case_kind(case)]


def normalise(text, out):
    # The scratch folder first: it may lie under anything else.
    for path, name in ((out, "{out}"), (FUZZ, "{fuzz}"), (HERE, "{dir}")):
        text = text.replace(path, name)
    return text


def snapshot(path):
    """What is at `path`: None (nothing), a file's bytes, or a dict of a folder's entries."""
    if os.path.islink(path) or os.path.isfile(path):
        with open(path, "rb") as f:
            return f.read()
    if os.path.isdir(path):
        return {name: snapshot(os.path.join(path, name)) for name in sorted(os.listdir(path))}
    return None


def prepare_out(case, out):
    """Sets up the case's output folder: "empty" (default), "absent", "file" (a regular file
    where the folder should be) or {"files": {name: corpus file}} (a folder holding copies)."""
    setup = case.get("out", "empty")
    if setup == "absent":
        return
    if setup == "file":
        with open(out, "w", encoding="utf-8") as f:
            f.write("a file where the output folder should be\n")
        return
    os.makedirs(out)
    if isinstance(setup, dict):
        for name, source in setup.get("files", {}).items():
            shutil.copyfile(os.path.join(HERE, source), os.path.join(out, name))


def describe_written(before, after):
    if after is None:
        return "removed the output folder"
    if isinstance(after, bytes):
        return "replaced the output folder by a file" if not isinstance(before, bytes) else \
            "changed the file given as output folder"
    if isinstance(before, bytes):
        return "replaced the file given as output folder by a folder"
    names = []
    for name in sorted(set(after) | set(before or {})):
        if (before or {}).get(name) != after.get(name):
            names.append(name)
    return "wrote to the output folder: " + ", ".join(names)


def run_case(cwe, case, commands, scratch, timeout):
    timeout = case.get("timeout", timeout)
    name = case_name(case)
    out = os.path.join(scratch, re.sub(r"[^A-Za-z0-9_.-]", "_", name), "out")
    os.makedirs(os.path.dirname(out))
    prepare_out(case, out)
    before = snapshot(out)
    args = [cwe] + [expand(a, case, out) for a in case_args(case, commands)]
    started = time.monotonic()
    try:
        done = subprocess.run(args, stdin=subprocess.DEVNULL, capture_output=True,
                              timeout=timeout, cwd=scratch)
        status, err = done.returncode, done.stderr
    except subprocess.TimeoutExpired as e:
        status, err = None, e.stderr or b""
    seconds = time.monotonic() - started
    after = snapshot(out)
    unchanged = after == before or (not before and not after)  # absent and empty are alike
    lines = normalise(err.decode("utf-8", "backslashreplace"), out).splitlines()
    return {
        "case": case, "name": name, "args": args, "out": out, "timeout": timeout,
        "status": status, "first": lines[0] if lines else "", "seconds": seconds,
        "written": None if unchanged else describe_written(before, after),
    }


def seen_line(result):
    """How cwe answered, as a known failure records it: "[exit status] first line"."""
    status = "timeout" if result["status"] is None else result["status"]
    return f"[{status}] {result['first']}"


def command_line(result):
    return " ".join(normalise(a, result["out"]) for a in result["args"][1:])


def judge(result):
    """The problems with a result (empty when the case passes), and whether it keeps the
    promise at all (for known failures)."""
    case = result["case"]
    problems = []
    if result["status"] is None:
        problems.append(f"no answer within {result['timeout']:g} s")
    elif result["status"] != case.get("exit", 2):
        problems.append(f"exit status {result['status']}, expected {case.get('exit', 2)}")
    if result["status"] is not None and result["status"] < 0:
        problems.append(f"killed by signal {-result['status']}")
    if "stderr" in case and result["first"] != case["stderr"]:
        problems.append(f"first line of stderr\n      expected: {case['stderr']}\n"
                        f"      actual:   {result['first']}")
    if "stderr" in case and not promised_form(case["stderr"]):
        problems.append("the expected line is not of the form 'source[:line[:col]]: error: …'")
    if result["written"]:
        problems.append(result["written"])
    keeps_promise = (result["status"] == 2 and promised_form(result["first"])
                     and not result["written"])
    return problems, keeps_promise


def write_manifest(manifest):
    """The manifest with one case a line, so that an update's diff reads case by case."""
    lines = ["{"]
    for key, value in manifest.items():
        if key == "cases":
            continue
        if isinstance(value, dict):
            lines.append(f"  {json.dumps(key)}: {{")
            for i, (k, v) in enumerate(value.items()):
                comma = "," if i + 1 < len(value) else ""
                lines.append(f"    {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}{comma}")
            lines.append("  },")
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value, ensure_ascii=False)},")
    lines.append('  "cases": [')
    cases = manifest["cases"]
    for i, case in enumerate(cases):
        comma = "," if i + 1 < len(cases) else ""
        lines.append("    " + json.dumps(case, ensure_ascii=False) + comma)
    lines.append("  ]")
    lines.append("}")
    with open(MANIFEST, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cwe", help="the cwe program")
    parser.add_argument("-k", dest="filter", default="",
                        help="run only the cases whose name contains this text")
    parser.add_argument("--update", action="store_true",
                        help="rewrite each case's expected first line from cwe's actual one "
                             "(not for known failures, nor for lines not in the promised form)")
    parser.add_argument("--strict", action="store_true",
                        help="fail on known failures that now keep the promise (XPASS)")
    parser.add_argument("--jobs", type=int, default=max(2, os.cpu_count() or 2),
                        help="cases run at once (default: the cores, at least 2)")
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds per case")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="list every case with its time and first line")
    options = parser.parse_args()
    cwe = os.path.abspath(options.cwe)
    if not os.access(cwe, os.X_OK):
        sys.exit(f"run.py: {cwe} is not an executable program")

    manifest = load_manifest()
    cases = [c for c in manifest["cases"] if options.filter in case_name(c)]
    names = [case_name(c) for c in manifest["cases"]]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        sys.exit("run.py: cases with the same name: " + ", ".join(duplicates))
    missing = [case_name(c) for c in cases if "input" in c and not os.path.exists(input_path(c))]
    if missing:
        sys.exit("run.py: inputs missing for: " + ", ".join(missing))

    # Every input in the corpus is some case's (the valid/ helpers and cli/ folders aside).
    used = {os.path.normpath(input_path(c)) for c in manifest["cases"] if "input" in c}
    for kind in sorted(manifest["commands"]):
        folder = os.path.join(HERE, kind)
        for name in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
            path = os.path.join(folder, name)
            if os.path.isfile(path) and path not in used and not name.endswith(HELPERS):
                sys.exit(f"run.py: {kind}/{name} is no case's input (add a case or remove it)")

    # Every fuzz finding is a case: in place (its path the input), or by its hash in a name
    # ("fuzz-0e1776f5") when the case holds a part of it (a tool-*.txt's spec line or JSON part).
    for name in sorted(os.listdir(FUZZ)) if os.path.isdir(FUZZ) else []:
        digest = re.search(r"-([0-9a-f]{8})[0-9a-f]*\.", name)
        if name == "README.md" or os.path.join(FUZZ, name) in used or (
                digest and any(f"fuzz-{digest.group(1)}" in n for n in names)):
            continue
        sys.exit(f"run.py: tests/data/fuzz-findings/{name} is no case's input (add a case)")

    corpus_before = snapshot(HERE)
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="cwe-malformed-") as scratch:
        with concurrent.futures.ThreadPoolExecutor(max_workers=options.jobs) as pool:
            results = list(pool.map(
                lambda c: run_case(cwe, c, manifest["commands"], scratch, options.timeout), cases))
    seconds = time.monotonic() - started

    failed, xfail, xpass, updated = [], [], [], []
    for result in results:
        case = result["case"]
        problems, keeps_promise = judge(result)
        if options.verbose:
            print(f"{result['seconds']:6.2f} s  {result['name']}: {seen_line(result)}")
        if "known_failure" in case:
            # A known failure is XFAIL while cwe answers as it did when it was marked ("seen");
            # an answer that changed and keeps the promise is XPASS, to be reviewed.
            if "seen" in case and seen_line(result) != case["seen"] and keeps_promise:
                xpass.append(result)
            else:
                xfail.append(result)
                if options.update and case.get("seen") != seen_line(result):
                    case["seen"] = seen_line(result)
                    updated.append(result["name"])
            continue
        if (options.update and case.get("stderr") != result["first"]
                and result["status"] == case.get("exit", 2) and not result["written"]
                and promised_form(result["first"])):
            case["stderr"] = result["first"]
            updated.append(result["name"])
            problems, _ = judge(result)
        if "stderr" not in case:
            problems.append("no expected first line (run --update)")
        if problems:
            failed.append((result, problems))

    for result, problems in failed:
        print(f"FAIL {result['name']}")
        print("    command: " + command_line(result))
        for problem in problems:
            print("    " + problem)
    for result in xfail:
        case = result["case"]
        changed_answer = seen_line(result) != case.get("seen")
        print(f"XFAIL {result['name']}: {case['known_failure']}\n"
              f"    command: {command_line(result)}\n    answer:  {seen_line(result)}"
              + (f"\n    (it answered {case.get('seen')} when marked)" if changed_answer else "")
              + (f"\n    {result['written']}" if result["written"] else ""))
    for result in xpass:
        print(f"XPASS {result['name']}: now answers {seen_line(result)}\n"
              f"    (was: {result['case'].get('seen')}); if that keeps the promise, remove "
              f"\"known_failure\" and \"seen\" and run --update")
    changed = snapshot(HERE) != corpus_before
    if changed:
        print("FAIL the corpus folder itself was changed by a run (git status tests/malformed)")
    if updated:
        write_manifest(manifest)
        print(f"updated the expected line of {len(updated)} cases: " + ", ".join(updated))

    kinds = {}
    for c in cases:
        kinds[case_kind(c)] = kinds.get(case_kind(c), 0) + 1
    print(f"{len(cases)} cases ({', '.join(f'{k} {n}' for k, n in sorted(kinds.items()))}) "
          f"in {seconds:.1f} s: {len(cases) - len(failed) - len(xfail) - len(xpass)} passed, "
          f"{len(failed)} failed, {len(xfail)} known failures (XFAIL), {len(xpass)} XPASS")
    bad = failed or changed or (options.strict and xpass)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
