#pragma once
// New feed rates written back into a toolpath program, in the program's own format.
//
// Feed-rate scheduling (cwe/process/feed_schedule.hpp) gives some source lines of a program a
// new feed (every move of one line, Move::line, gets the same). rewrite_feeds() returns the
// program text changed so that reading it again (read_gcode, read_cldata) gives every feed move
// of a listed line the new feed and every other move exactly what it had: the same positions,
// axes, arcs, rapids, spindle and tool, and the same feed. Nothing else changes: line endings,
// comments, blanks, case and numbering are kept byte for byte.
//
// Both formats carry the feed modally, so the rewrite tracks two feeds down the program: the one
// the original program has in force and the one the rewritten program has. A listed line gets its
// feed where it differs from the rewritten program's; an unlisted line that feeds gets the
// original feed back where an earlier change left the two apart.
//
// G-code (RS274NGC as cwe/toolpath/gcode_reader.hpp reads it; docs/gcode.md): on a listed line
// the number of its F word is replaced or, without one, a word ` F<feed>` is added after the last
// word of the line (before a trailing `( … )` or `;` comment). F is in program units per minute:
// the units in force before the line's own G20/G21 (the reader executes F before G20/G21 on a
// line, as LinuxCNC does), mm/25.4 in G20. A new feed keeps the program's precision: it is
// rounded down (so never above the feed asked for) to as many decimals as the program's F words
// have at most (its post's precision), in inches at least 1; 1 in mm and 2 in inches for a
// program with no F word; more (up to 4 in mm, 5 in inches) only when that would write 0.
// Trailing zeros are stripped (F812, F812.5, F22.7). A restored feed is written as its original
// F word was when the units are the same (so it is exact), converted otherwise (5 decimals in
// inches, 4 in mm, to the nearest).
//
// APT CLDATA (as cwe/toolpath/cldata_reader.hpp reads it; docs/cldata.md): a line
// `FEDRAT/<feed>,MMPM` (`IPM` under UNITS/INCHES; rounded down to the program's precision as
// for G-code, from its FEDRAT numbers; `FEDRAT/MMPM,<feed>` if the program writes the unit
// first; in lower case if the motion record is) is inserted before the motion record, with that line's
// indentation and line ending: before the first line of a record continued with `$`, and before
// the CIRCLE record of an arc unless a FEDRAT already stands between the CIRCLE and its GOTO. A
// restored feed repeats the original FEDRAT's number with its unit made explicit (MMPM, IPM, or
// MMPR, IPR for feeds per revolution), so it is exact whatever UNITS says. A line of bare numbers
// that continues a GOTO (Creo) cannot be preceded by a record; when its feed must change it
// becomes a GOTO of its own (`GOTO/` is added before its numbers, after a copy of the CIRCLE
// record, without TIMES, when the point ends an arc piece), which the reader makes into the same
// move.
//
// Errors:
//  - cwe::InputError (source and line) for a `feeds` entry that cannot be written: a feed that is not a
//    finite number > 0 (mm/min), one that rounds to 0 or exceeds kLargestInputValue in the
//    program's number format, or a line that has no feed move (no motion, only rapids, a CIRCLE
//    or FEDRAT record, the inside of a continued record, past the end). The message names the
//    source and the line.
//  - cwe::InputError (source, line, column) for a program the readers refuse (it is read first,
//    with its own message) and for an F word that cannot be rewritten: its number is a parameter
//    or an expression (`F#1`, `F[…]`), or is interrupted by a comment. Lines executed several
//    times (loops, subroutine calls) take one feed, the one given for the line; feed moves from
//    subroutine files are not the program text's lines and are left alone.

#include <map>
#include <string>
#include <string_view>

#include "cwe/toolpath/gcode_reader.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe {

// New feed rates, mm/min, by source line (from 1) of the program text.
using LineFeeds = std::map<int, double>;

struct FeedRewriteOptions {
  // The options the G-code program is read with: its initial units scale the F words before any
  // G20/G21. Ignored for CLDATA.
  GcodeOptions gcode;
};

// The program `text` in `format` with the feeds of the lines in `feeds` changed (see above);
// `source` names it in errors. With `feeds` empty the text comes back unchanged.
std::string rewrite_feeds(std::string_view text, ToolpathFormat format, const LineFeeds& feeds,
                          const std::string& source, const FeedRewriteOptions& options = {});

}  // namespace cwe
