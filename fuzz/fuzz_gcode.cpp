// G-code programs (cwe::read_gcode). The program's folder does not exist and the subroutine path
// is empty, so a call of an undefined subroutine finds no file (only an absolute name could
// name one). Moves are streamed (as `cwe simulate` reads them) and the run stops after
// kMaxMoves: a loop that moves a billion times is a long program, not a finding; for the same
// reason a loop without moves is refused after 10,000 iterations instead of 10 million, and
// reading stops after 200,000 lines (loops nested in loops that move).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "cwe/toolpath/gcode_reader.hpp"
#include "fuzz_check.hpp"

namespace {

constexpr std::size_t kMaxMoves = 20'000;
struct EnoughMoves {};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::string source = "/nonexistent-cwe-fuzz/input.ngc";
  cwe::GcodeOptions options;
  options.max_idle_iterations = 10'000;
  options.max_lines_read = 200'000;
  // Tools 1 … 20 have diameters, so that cutter radius compensation (G41/G42) runs.
  options.tool_diameter = [](int tool) -> std::optional<double> {
    if (tool >= 1 && tool <= 20) return 1.5 * tool;
    return std::nullopt;
  };
  std::size_t moves = 0;
  const cwe::MoveSink sink = [&](const cwe::Move&, const std::vector<std::string>&) {
    if (++moves > kMaxMoves) throw EnoughMoves{};
  };
  cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLine, [&] {
    try {
      (void)cwe::read_gcode(text, source, options, sink);
    } catch (const EnoughMoves&) {
    }
  });
  return 0;
}
