#!/usr/bin/python3
"""Writes the golden move list of a G-code program as LinuxCNC's interpreter produces it.

Usage (needs LinuxCNC, e.g. Debian's linuxcnc-uspace, and its Python 3 module `gcode`):

    /usr/bin/python3 linuxcnc_oracle.py program.ngc > program.golden

The program is run through LinuxCNC's RS274NGC interpreter (gcode.parse, the interpreter AXIS
uses for its preview) with no tool table and zero offsets. Every canonical motion call becomes one
line, lengths in mm with 17 significant digits:

    rapid <line> <x> <y> <z>                                  STRAIGHT_TRAVERSE
    feed  <line> <x> <y> <z>                                  STRAIGHT_FEED
    arc   <line> <plane> <x> <y> <z> <c1> <c2> <rotation>     ARC_FEED

x y z is the end point; c1 c2 the centre in the plane's canonical axis order (XY: X Y,
XZ: Z X, YZ: Y Z); rotation LinuxCNC's turn count: +n counter-clockwise about the plane's normal
axis (Z, Y, X), -n clockwise, |n| - 1 extra full turns. An interpreter error ends the list with
`error <line> <message>`. cwe's tests (gcode_reader_test.cpp) read these files; they never run
LinuxCNC. With --flags before the program, lines `flag <what>` also name what cwe's reader does
not model: rotary (A, B, C motion), uvw, io (digital or analog I/O), probe
(scripts/linuxcnc_compare.py leaves such programs out). G33.1 (rigid tapping, one canonical call)
is written as the preview draws it: a feed to the bottom and one back.
"""
import os
import sys
import tempfile

import gcode
from rs274.interpret import Translated, ArcsToSegmentsMixin

MM_PER_INCH = 25.4  # the module reports every length in inches, whatever the program's units
PLANES = {1: "XY", 3: "XZ", 2: "YZ"}  # gcode module plane codes


def fmt(v):
    return "%.17g" % (v * MM_PER_INCH)


class Canon(Translated, ArcsToSegmentsMixin):
    def __init__(self):
        self.lines = []
        self.lineno = 0
        self.plane = 1
        self.parameter_file = ""
        self.lo = (0.0,) * 9
        self.flags = set()

    def note_axes(self, a):
        if any(abs(v) > 1e-12 for v in a[3:6]):
            self.flags.add("rotary")
        if any(abs(v) > 1e-12 for v in a[6:9]):
            self.flags.add("uvw")

    # Queries the interpreter makes.
    def get_external_angular_units(self): return 1.0
    def get_external_length_units(self): return 1.0
    def get_axis_mask(self): return 7  # X, Y, Z
    def get_block_delete(self): return 0
    def get_tool(self, pocket): return (-1,) + (0.0,) * 12 + (0,)

    def next_line(self, state): self.lineno = state.sequence_number
    def set_plane(self, plane): self.plane = plane

    # Canonical positions are in the program's coordinates; Translated's rotate_and_translate
    # adds the G92 and G5x offsets (and the XY rotation) to give machine coordinates, which cwe
    # reports.
    def machine(self, a):
        a = tuple(a) + (0.0,) * (9 - len(a))
        return self.rotate_and_translate(*a)

    def straight_traverse(self, *a):
        a = self.machine(a)
        self.note_axes(a)
        self.lo = tuple(a)
        self.lines.append("rapid %d %s %s %s" % (self.lineno, fmt(a[0]), fmt(a[1]), fmt(a[2])))

    def straight_feed(self, *a):
        a = self.machine(a)
        self.note_axes(a)
        self.lo = tuple(a)
        self.lines.append("feed %d %s %s %s" % (self.lineno, fmt(a[0]), fmt(a[1]), fmt(a[2])))

    def arc_feed(self, first_end, second_end, first_center, second_center, rotation, axis_end,
                 *rest):
        def xyz(first, second, axis):
            if self.plane == 1:
                return first, second, axis
            if self.plane == 3:
                return second, axis, first
            return axis, first, second

        def plane_of(p):
            if self.plane == 1:
                return p[0], p[1]
            if self.plane == 3:
                return p[2], p[0]
            return p[1], p[2]

        end = self.machine(xyz(first_end, second_end, axis_end) + tuple(rest[:3]))
        x, y, z = end[0:3]
        first_center, second_center = plane_of(
            self.machine(xyz(first_center, second_center, axis_end))[0:3])
        self.lo = (x, y, z) + tuple(end[3:6]) + (0.0, 0.0, 0.0)
        self.note_axes(self.lo)
        self.lines.append("arc %d %s %s %s %s %s %s %d" % (
            self.lineno, PLANES[self.plane], fmt(x), fmt(y), fmt(z), fmt(first_center),
            fmt(second_center), rotation))

    def rigid_tap(self, x, y, z, *rest):
        # G33.1: to the point and back (the preview's two moves; the canonical call is one).
        start = self.lo
        a = self.machine((x, y, z))
        self.lines.append("feed %d %s %s %s" % (self.lineno, fmt(a[0]), fmt(a[1]), fmt(a[2])))
        self.lines.append("feed %d %s %s %s" % (self.lineno, fmt(start[0]), fmt(start[1]),
                                                 fmt(start[2])))

    IO = ("set_motion_output_bit", "clear_motion_output_bit", "set_aux_output_bit",
          "clear_aux_output_bit", "set_motion_output_value", "set_aux_output_value", "wait")
    OTHER = {"straight_probe": "probe"}

    def __getattr__(self, name):  # every other canonical call: no motion
        if name.startswith("__"):
            raise AttributeError(name)
        if name.startswith(self.IO):
            self.flags.add("io")
        elif name in self.OTHER:
            self.flags.add(self.OTHER[name])
        return lambda *a, **k: None


def main():
    flags = sys.argv[1] == "--flags"
    program = os.path.abspath(sys.argv[-1])
    os.chdir(tempfile.mkdtemp())  # the interpreter leaves rs274ngc.var files behind
    canon = Canon()
    # A metric machine: G21 until the program says otherwise, as cwe reads programs by default.
    result, line = gcode.parse(program, canon, "G21", "")
    print("# LinuxCNC interpreter (python3 gcode module) moves for %s; lengths in mm"
          % os.path.basename(program))
    for text in canon.lines:
        print(text)
    if result > gcode.MIN_ERROR:
        print("error %d %s" % (line, gcode.strerror(result)))
    if flags:
        for flag in sorted(canon.flags):
            print("flag %s" % flag)
    sys.stdout.flush()
    os._exit(0)  # the module can crash while Python tears it down; the output is complete


if __name__ == "__main__":
    main()
