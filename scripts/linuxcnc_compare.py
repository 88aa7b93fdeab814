#!/usr/bin/python3
"""Compares cwe's G-code reader with LinuxCNC's interpreter, program by program.

Usage (needs LinuxCNC's Python module `gcode`, e.g. Debian's linuxcnc-uspace, and a built cwe):

    /usr/bin/python3 scripts/linuxcnc_compare.py [--cwe build/cwe] [--subroutine-path A:B]
        [--list FILES.txt] [--out report.md] PROGRAM_OR_FOLDER...

For each program, LinuxCNC's interpreter (tests/toolpath/golden/linuxcnc_oracle.py, with the
subroutine path given to it through an INI file) and `cwe path --dump` list the moves; the program
matches when both list the same moves, kinds and end points within 1e-6 mm, and for arcs the same
centres (within that plus cwe's bisector shift for rounded data), directions and turns. LinuxCNC's Python
module crashes on programs that use tool data (T, H); those are run through `rs274 -g` instead,
whose output has four decimals in program units, so they match within 0.6e-4 of a unit.
Programs LinuxCNC itself refuses, and programs with rotary motion or digital/analog I/O, are
reported apart and not counted. The report gives the fraction matched and, for the others, the
first difference or cwe's error.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ORACLE = os.path.join(HERE, "..", "tests", "toolpath", "golden", "linuxcnc_oracle.py")
TOLERANCE = 1e-6  # mm
# The tool table both interpreters get: tools 1-99, 1/16 in end mills (rs274 reads a table's
# diameters in inches; cwe's JSON table is in mm). Cutter radius compensation offsets by them.
TOOLS = range(1, 100)
TOOL_DIAMETER_INCH = 0.0625


def cwe_tool_table(folder):
    table = os.path.join(folder, "tools.json")
    with open(table, "w") as t:
        json.dump({str(n): "flat:%g" % (TOOL_DIAMETER_INCH * 25.4) for n in TOOLS}, t)
    return table


def oracle(program, ini):
    env = dict(os.environ, INI_FILE_NAME=ini)
    try:
        run = subprocess.run(["/usr/bin/python3", ORACLE, "--flags", program], capture_output=True,
                             text=True, timeout=60, env=env)
    except subprocess.TimeoutExpired:
        return None, "LinuxCNC timed out", set()
    if not run.stdout.startswith("#"):  # the module crashed (tool data): rs274 instead
        return None, None, None
    moves, flags, error = [], set(), None
    for line in run.stdout.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        words = line.split()
        if words[0] == "error":
            error = " ".join(words[2:])
        elif words[0] == "flag":
            flags.add(words[1])
        else:
            moves.append(words)
    return moves, error, flags


def rs274(program, ini):
    """LinuxCNC's standalone interpreter: moves as (kind, line, x, y, z) in mm, offsets applied."""
    folder = tempfile.mkdtemp()
    table = os.path.join(folder, "tools.tbl")
    with open(table, "w") as t:
        for n in TOOLS:
            t.write("T%d P%d D%g Z0\n" % (n, n, TOOL_DIAMETER_INCH))
    canon = os.path.join(folder, "out.canon")
    try:
        run = subprocess.run(["rs274", "-g", "-i", ini, "-t", table, program, canon],
                             stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60,
                             cwd=folder)
    except (subprocess.TimeoutExpired, FileNotFoundError) as e:
        return None, "rs274: %s" % e, set(), 0.0
    if run.returncode != 0 or not os.path.exists(canon):
        message = (run.stdout + run.stderr).strip().splitlines()
        return None, message[0] if message else "rs274 failed", set(), 0.0
    scale, plane, offset, moves, flags, precision = 1.0, "XY", [0.0] * 3, [], set(), 0.0
    last = [0.0] * 3
    g5x, g92 = [0.0] * 3, [0.0] * 3
    for line in open(canon):
        text = line.split(None, 2)[2].strip() if len(line.split(None, 2)) == 3 else ""
        name, _, rest = text.partition("(")
        args = rest.rstrip(")").replace(" ", "").split(",") if rest else []
        if name == "USE_LENGTH_UNITS":
            scale = 25.4 if "INCHES" in text else 1.0
            precision = max(precision, 0.6e-4 * scale)
        elif name == "SELECT_PLANE":
            plane = text.split("CANON_PLANE_")[1].rstrip(")")
        elif name == "SET_G5X_OFFSET":
            g5x = [float(v) * scale for v in args[1:4]]
        elif name == "SET_G92_OFFSET":
            g92 = [float(v) * scale for v in args[0:3]]
        elif name == "SET_XY_ROTATION" and abs(float(args[0])) > 1e-12:
            flags.add("rotation")
        elif name == "RIGID_TAP":  # G33.1: to the point and back
            a = [float(v) for v in args]
            end = [a[k] * scale + g5x[k] + g92[k] for k in range(3)]
            moves.append(["feed", "?"] + ["%.17g" % v for v in end])
            moves.append(["feed", "?"] + ["%.17g" % v for v in last])
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED"):
            a = [float(v) for v in args]
            if name == "ARC_FEED":
                e1, e2, ax = a[0], a[1], a[5]
                p = {"XY": (e1, e2, ax), "XZ": (e2, ax, e1), "YZ": (ax, e1, e2)}[plane]
                extra = a[6:9]
            else:
                p, extra = a[0:3], a[3:6]
            if any(abs(v) > 1e-12 for v in extra):
                flags.add("rotary")
            end = [p[k] * scale + g5x[k] + g92[k] for k in range(3)]
            kind = {"STRAIGHT_TRAVERSE": "rapid", "STRAIGHT_FEED": "feed", "ARC_FEED": "arc"}[name]
            if kind == "arc":  # the centre in the plane's order, and the signed turns
                i, j = {"XY": (0, 1), "XZ": (2, 0), "YZ": (1, 2)}[plane]
                centre = [a[2] * scale + g5x[i] + g92[i], a[3] * scale + g5x[j] + g92[j]]
                moves.append(["arc", "?", plane] + ["%.17g" % v for v in end + centre] +
                             ["%d" % int(a[4])])
            else:
                moves.append([kind, "?"] + ["%.17g" % v for v in end])
            last = end
        elif name.startswith(("SET_MOTION_OUTPUT", "SET_AUX_OUTPUT", "CLEAR_MOTION_OUTPUT",
                              "CLEAR_AUX_OUTPUT", "WAIT")):
            flags.add("io")
        elif name == "STRAIGHT_PROBE":
            flags.add("probe")
    return moves, None, flags, max(precision, 0.6e-4)


def cwe_moves(cwe, program, path, tools):
    args = [cwe, "path", program, "--dump", "--tools", tools]
    if path:
        args += ["--subroutine-path", path]
    try:
        run = subprocess.run(args, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        return None, "cwe timed out"
    if run.returncode != 0:
        return None, (run.stderr.strip().splitlines() or ["exit %d" % run.returncode])[0]
    return [json.loads(l) for l in run.stdout.splitlines()], None


def compare(reference, moves, tolerance=TOLERANCE):
    """None when the moves agree: kinds and ends; for arcs also the centre (within the tolerance
    plus the shift onto the chord's bisector that cwe makes when the radii to start and end
    differ, |r1² - r2²| / (2 chord)), the direction and the turns."""
    if len(reference) != len(moves):
        return "%d moves, LinuxCNC %d" % (len(moves), len(reference))
    start = [0.0] * 3
    for k, (r, m) in enumerate(zip(reference, moves)):
        kind = r[0]
        end = [float(v) for v in (r[3:6] if kind == "arc" else r[2:5])]
        mk = m["type"]
        where = "move %d (line %s)" % (k + 1, r[1])
        if (kind, mk) not in (("rapid", "rapid"), ("feed", "feed"), ("arc", "arc")):
            return "%s: %s, LinuxCNC %s" % (where, mk, kind)
        if max(abs(a - b) for a, b in zip(end, m["end"])) > tolerance:
            return "%s: end %s, LinuxCNC %s" % (where, m["end"], end)
        if kind == "arc":
            a1, a2, a3 = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}[r[2]]
            c1, c2, turns = float(r[6]), float(r[7]), int(r[8])
            r1 = math.hypot(start[a1] - c1, start[a2] - c2)
            r2 = math.hypot(end[a1] - c1, end[a2] - c2)
            chord = math.hypot(end[a1] - start[a1], end[a2] - start[a2])
            shift = abs(r1 * r1 - r2 * r2) / (2 * chord) if chord > 1e-9 else 0.0
            centre = m["center"]
            if max(abs(centre[a1] - c1), abs(centre[a2] - c2)) > tolerance + shift:
                return "%s: centre %s, LinuxCNC %s %s" % (where, centre, c1, c2)
            if m["normal"][a3] * turns <= 0 or m["turns"] + 1 != abs(turns):
                return "%s: normal %s and %d extra turns, LinuxCNC turns %d" % (
                    where, m["normal"], m["turns"], turns)
        start = end
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("programs", nargs="*")
    parser.add_argument("--cwe", default=os.path.join(HERE, "..", "build", "cwe"))
    parser.add_argument("--subroutine-path", default="")
    parser.add_argument("--list", help="a file naming one program per line")
    parser.add_argument("--out", help="write the report here (default: standard output)")
    args = parser.parse_args()
    programs = []
    for p in args.programs:
        if os.path.isdir(p):
            programs += sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith(".ngc"))
        else:
            programs.append(p)
    if args.list:
        base = args.programs[0] if args.programs and os.path.isdir(args.programs[0]) else ""
        programs = [os.path.join(base, l.strip()) for l in open(args.list) if l.strip()]
    ini = tempfile.NamedTemporaryFile("w", suffix=".ini", delete=False)
    ini.write("[RS274NGC]\nSUBROUTINE_PATH = %s\n" % args.subroutine_path)
    ini.close()
    tools = cwe_tool_table(tempfile.mkdtemp())
    rows, counted, matched, excluded = [], 0, 0, 0
    for program in programs:
        program = os.path.abspath(program)
        name = os.path.basename(program)
        reference, error, flags = oracle(program, ini.name)
        tolerance, by = TOLERANCE, ""
        if flags is None:
            reference, error, flags, tolerance = rs274(program, ini.name)
            by = " (rs274, within %.2g mm)" % tolerance
        if error or reference is None or flags:
            excluded += 1
            rows.append((name, "not counted", error or ", ".join(sorted(flags))))
            continue
        counted += 1
        moves, failure = cwe_moves(args.cwe, program, args.subroutine_path, tools)
        if moves is not None:
            failure = compare(reference, moves, tolerance)
        if failure is None:
            matched += 1
            rows.append((name, "match", "%d moves%s" % (len(reference), by)))
        else:
            rows.append((name, "differs", failure))
    out = open(args.out, "w") if args.out else sys.stdout
    out.write("# cwe's G-code reader against LinuxCNC's interpreter\n\n")
    out.write("%d of %d programs match move for move (%.0f %%); %d not counted (LinuxCNC refuses "
              "them, or they move rotary axes or use I/O).\n\n"
              % (matched, counted, 100.0 * matched / max(counted, 1), excluded))
    out.write("| program | result | detail |\n| --- | --- | --- |\n")
    for name, result, detail in rows:
        out.write("| %s | %s | %s |\n" % (name, result, detail.replace("|", "\\|")))
    os.unlink(ini.name)


if __name__ == "__main__":
    main()
