#!/usr/bin/env python3
"""A run of `cwe simulate` killed at any point leaves its output folder with the previous run's
complete set or the new run's complete set, never a mix, and at most one staging folder beside it,
which the next run removes (docs/simulate.md, "Outputs").

    kill_test.py CWE_BINARY SOURCE_DIR [--kills 20] [--seed 17]

Two settings (resolution 0.5 and 0.4 mm on the bundled pocket program) give two reference sets.
Runs alternate between them into one folder and are killed with SIGKILL after a random delay in
[0, 1.2 × a full run's time]; after each kill the folder must equal one of the references.
"""

import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# Fields of summary.json that differ between two runs of the same job.
VOLATILE = {"seconds", "seconds_by_stage"}


def command(cwe, source, resolution, out):
    return [cwe, "simulate", "--stock", "box:0,0,-30,100,60,0", "--tool", "flat:10,30",
            "--path", str(source / "examples" / "programs" / "pocket.ngc"),
            "--resolution", str(resolution), "--threads", "1", "--out", str(out), "--quiet"]


def snapshot(folder):
    """The folder's files (relative path -> bytes, summary.json without its volatile fields)."""
    files = {}
    for path in sorted(Path(folder).rglob("*")):
        if path.is_file():
            data = path.read_bytes()
            if path.name == "summary.json":
                summary = json.loads(data)
                for key in VOLATILE:
                    summary.pop(key, None)
                data = json.dumps(summary, sort_keys=True).encode()
            files[str(path.relative_to(folder))] = data
    return files


def leftovers(folder):
    parent, name = Path(folder).parent, Path(folder).name
    return sorted(p.name for p in parent.iterdir() if p.name.startswith("." + name + ".cwe-"))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("cwe")
    parser.add_argument("source", type=Path)
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--seed", type=int, default=17)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    failures = []
    with tempfile.TemporaryDirectory(prefix="cwe-kill-") as scratch:
        scratch = Path(scratch)
        settings = [0.5, 0.4]
        references, seconds = [], []
        for k, resolution in enumerate(settings):
            folder = scratch / f"reference{k}"
            started = time.monotonic()
            subprocess.run(command(args.cwe, args.source, resolution, folder), check=True,
                           stdout=subprocess.DEVNULL)
            seconds.append(time.monotonic() - started)
            references.append(snapshot(folder))
        assert references[0] != references[1], "the two settings must give different sets"
        out = scratch / "out"
        subprocess.run(command(args.cwe, args.source, settings[0], out), check=True,
                       stdout=subprocess.DEVNULL)
        completed = 0
        for kill in range(args.kills):
            resolution = settings[(kill + 1) % 2]
            delay = rng.uniform(0.0, 1.2 * max(seconds))
            run = subprocess.Popen(command(args.cwe, args.source, resolution, out),
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(delay)
            if run.poll() is None:
                run.send_signal(signal.SIGKILL)
            else:
                completed += 1
            run.wait()
            now = snapshot(out) if out.exists() else None
            if now not in references:
                names = sorted(now) if now is not None else "no folder"
                failures.append(f"kill {kill} after {delay:.2f} s: the folder is neither set "
                                f"({names})")
            if len(leftovers(out)) > 1:
                failures.append(f"kill {kill}: more than one staging folder: {leftovers(out)}")
        # The next complete run removes what the killed ones left.
        subprocess.run(command(args.cwe, args.source, settings[0], out), check=True,
                       stdout=subprocess.DEVNULL)
        if snapshot(out) != references[0]:
            failures.append("the last complete run did not give its set")
        if leftovers(out):
            failures.append(f"the last complete run left {leftovers(out)}")
        print(f"{args.kills} kills ({completed} runs finished before their kill), "
              f"full runs {seconds[0]:.2f} s and {seconds[1]:.2f} s")
    for failure in failures:
        print("FAIL:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
