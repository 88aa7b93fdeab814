#include "schedule_command.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/job/feed_allowance.hpp"
#include "cwe/job/run.hpp"
#include "cwe/process/feed_schedule.hpp"
#include "cwe/toolpath/feed_rewrite.hpp"
#include "job_file.hpp"

namespace cwe::app {

namespace {

// One operation's result: the program text and what changed.
// One operation's schedule.
struct ScheduledProgram {
  Schedule schedule;
  int first_exceeded_line = 0;
};

// A program to rewrite: its operations' feeds by line, and where the result goes.
struct ScheduledFile {
  std::string path;
  ToolpathFormat format = ToolpathFormat::kGcode;
  std::filesystem::path target;
  LineFeeds lines;
  GcodeOptions gcode;  // what the job read it with
};

// Where each scheduled program goes: --out itself for one program, else --out/<its name>; no
// two programs to one file, and never over an input. A program that changes tools runs as
// several operations (one per tool) and is written once, with the feeds of all of them.
// `file_of` gets the file of each operation.
std::vector<ScheduledFile> scheduled_files(const PreparedJob& job, const std::string& out,
                                           std::vector<std::size_t>& file_of) {
  std::vector<ScheduledFile> files;
  for (const PreparedOperation& op : job.operations) {
    const auto known = std::find_if(files.begin(), files.end(),
                                    [&](const ScheduledFile& f) { return f.path == op.path; });
    if (known != files.end()) {
      file_of.push_back(static_cast<std::size_t>(known - files.begin()));
      continue;
    }
    file_of.push_back(files.size());
    files.push_back({op.path, op.format, {}, {}, op.gcode});
  }
  // A program whose moves come from other files too cannot be rewritten whole.
  for (const PreparedOperation& op : job.operations) {
    if (op.moves_from_other_files) {
      throw InputError(SourceLocation{op.path},
                       "the program includes other files; scheduling rewrites one file only");
    }
  }
  for (ScheduledFile& file : files) {
    const PreparedOperation& op =
        *std::find_if(job.operations.begin(), job.operations.end(),
                      [&](const PreparedOperation& o) { return o.path == file.path; });
    const std::filesystem::path target =
        files.size() == 1 ? std::filesystem::path(out)
                          : std::filesystem::path(out) / std::filesystem::path(op.path).filename();
    const auto same = [&](const std::filesystem::path& other) {
      std::error_code ec;
      return std::filesystem::weakly_canonical(target, ec) ==
             std::filesystem::weakly_canonical(other, ec);
    };
    if (std::any_of(files.begin(), files.end(),
                    [&](const ScheduledFile& f) { return !f.target.empty() && same(f.target); })) {
      throw InputError(SourceLocation{"--out"},
                       fmt::format("two operations would write {}: give their programs different "
                                   "names",
                                   target.string()));
    }
    for (const PreparedOperation& other : job.operations) {
      if (same(other.path)) {
        throw InputError(
            SourceLocation{"--out"},
            fmt::format("{} is an input program: write the schedule elsewhere", target.string()));
      }
    }
    file.target = target;
  }
  return files;
}

// Each operation's schedule from the feeds its moves allow; the new feeds go to their file's lines.
std::vector<ScheduledProgram> schedule_operations(const PreparedJob& job,
                                                  const FeedAllowance& allowance,
                                                  const ScheduleOptions& bounds,
                                                  std::vector<ScheduledFile>& files,
                                                  const std::vector<std::size_t>& file_of) {
  std::vector<ScheduledProgram> programs;
  std::size_t moves_before = 0, i = 0;  // moves of the operations before; of this one
  std::vector<MoveFeed> feeds;
  std::vector<SourceLocation> at;  // of each feed move scheduled
  OperationVisitor visitor;
  visitor.begin = [&](std::size_t) {
    i = 0;
    feeds.clear();
    at.clear();
  };
  visitor.move = [&](const Move& m, const std::vector<std::string>& sources) {
    const double programmed = feed_rate(m, *job.forces);
    const std::optional<double> allowed = allowance.allowed()[moves_before + i++];
    if (!(programmed > 0.0)) return;
    feeds.push_back({programmed, allowed, m.length()});
    at.push_back(
        SourceLocation{m.source > 0 ? sources[static_cast<std::size_t>(m.source)] : "", m.line});
  };
  visitor.end = [&](std::size_t o) {
    const PreparedOperation& op = job.operations[o];
    ScheduledProgram program;
    program.schedule = schedule_feeds(feeds, bounds);
    LineFeeds& lines = files[file_of[o]].lines;
    for (std::size_t f = 0; f < at.size(); ++f) {
      if (!at[f].source.empty()) {
        throw InputError(at[f],
                         fmt::format("a feed move of {} comes from this subroutine file: cwe "
                                     "schedule rewrites the feeds of the program file only (put "
                                     "the subroutine in the program to schedule it)",
                                     op.path));
      }
      const ScheduledMove& s = program.schedule.moves[f];
      auto [it, inserted] = lines.emplace(at[f].line, s.feed);
      if (!inserted) it->second = std::min(it->second, s.feed);
      if (s.limit_exceeded && program.first_exceeded_line == 0) {
        program.first_exceeded_line = at[f].line;
      }
    }
    programs.push_back(std::move(program));
    moves_before += i;
  };
  for_each_move(job, visitor);
  return programs;
}

// The terminal report: the limit, each operation's changes and the programs written.
void print_schedule_report(std::ostream& out, const FeedLimit& limit, const PreparedJob& job,
                           const std::vector<ScheduledProgram>& programs,
                           const std::vector<ScheduledFile>& files) {
  const char* unit = limit.quantity == FeedLimit::Quantity::kForce    ? "N"
                     : limit.quantity == FeedLimit::Quantity::kTorque ? "N·m"
                     : limit.quantity == FeedLimit::Quantity::kPower  ? "W"
                                                                      : "mm";
  fmt::print(out, "cwe schedule: limit {} {:g} {} ({})\n", to_string(limit.quantity), limit.value,
             unit, coefficient_names(job));
  for (std::size_t o = 0; o < programs.size(); ++o) {
    const ScheduledProgram& p = programs[o];
    const Schedule& s = p.schedule;
    const double change = s.programmed_minutes > 0.0
                              ? 100.0 * (s.scheduled_minutes / s.programmed_minutes - 1.0)
                              : 0.0;
    const PreparedOperation& op = job.operations[o];
    fmt::print(out,
               "  {}{}: {} feed moves, {} slowed, {} sped up; feed time {:.2f} min -> {:.2f} min "
               "({:+.1f}%)\n",
               op.path, op.tool != 0 ? fmt::format(" (tool {})", op.tool) : std::string(),
               s.moves.size(), s.limited, s.raised, s.programmed_minutes, s.scheduled_minutes,
               change);
    if (s.exceeded > 0) {
      fmt::print(out,
                 "  warning: {} moves exceed the limit even at the lowest feed (first: line {}); "
                 "lower --min-feed/--min-scale or the depth of cut\n",
                 s.exceeded, p.first_exceeded_line);
    }
  }
  for (const Diagnostic& d : job.warnings) fmt::print(out, "  warning: {}\n", d.message);
  for (const ScheduledFile& file : files) {
    fmt::print(out, "  scheduled program: {}\n", file.target.string());
  }
}

}  // namespace

void add_schedule_command(CLI::App& app, ScheduleCommandOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "schedule",
      "Feed-rate scheduling: run the job of 'cwe simulate' with --forces, find at every cutter "
      "location the largest feed that keeps --limit, and write the program again with only its "
      "feeds changed (G-code F words or CLDATA FEDRAT records). See docs/forces.md.");
  add_job_options(cmd, options.job);
  cmd->add_option("--limit", options.limit,
                  "The limit: force=<N> (peak resultant), torque=<N·m> (peak), power=<W or kW> "
                  "(mean) or chip=<mm> (thickest chip), e.g. force=800N")
      ->required();
  cmd->add_option("--out", options.out,
                  "The scheduled program (a folder when the job has several operations)")
      ->required();
  cmd->add_option("--min-feed", options.min_feed, "Lowest feed, mm/min (default: none)");
  cmd->add_option("--max-feed", options.max_feed, "Highest feed, mm/min (default: none)");
  cmd->add_option("--min-scale", options.min_scale,
                  "Lowest feed as a fraction of each move's programmed feed (default 0.1)");
  cmd->add_option("--max-scale", options.max_scale,
                  "Highest feed as a fraction of each move's programmed feed (default 2)");
  cmd->add_option("--max-change", options.max_change,
                  "Largest ratio between the feeds of consecutive feed moves (default 1.5)");
}

int run_schedule_command(ScheduleCommandOptions options, std::ostream& out,
                         std::ostream* progress) {
  SimulateCommandOptions& sim = options.job;
  read_job(sim);
  if (!sim.report_units.empty()) {
    throw InputError(SourceLocation{"--report-units"},
                     "cwe schedule writes the program in its own units and reports no lengths; "
                     "the option is for cwe simulate");
  }
  const FeedLimit limit = parse_feed_limit(options.limit, "--limit");
  ScheduleOptions bounds;
  bounds.min_scale = options.min_scale;
  bounds.max_scale = options.max_scale;
  bounds.max_change = options.max_change;
  if (options.min_feed != 0.0) bounds.min_feed = options.min_feed;  // 0: not given
  if (options.max_feed != 0.0) bounds.max_feed = options.max_feed;
  try {
    bounds.check();  // before the long part, not after it
  } catch (const InputError& e) {
    throw InputError(SourceLocation{"cwe schedule"},
                     fmt::format("{} (--min-scale, --max-scale, --min-feed, --max-feed, "
                                 "--max-change)",
                                 e.message()));
  }
  PreparedJob job = prepare_job(sim);
  if (!job.forces) {
    throw InputError(SourceLocation{"cwe"},
                     "no cutting coefficients: give --forces, put it in a job file, or give each "
                     "tool its \"forces\" in the tool table");
  }
  std::vector<std::size_t> file_of;  // per operation
  std::vector<ScheduledFile> files = scheduled_files(job, options.out, file_of);
  const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                        static_cast<std::size_t>(job.threads));
  JobStock stock = make_job_stock(job);
  ProgressBar bar(sim.quiet ? nullptr : progress);
  const std::size_t all_moves = move_count(job);
  FeedAllowance allowance(all_moves, limit, bounds);
  ClSink* const sinks[] = {&allowance};
  run_job(job, std::move(stock), RunOptions{true, false}, sinks,
          [&](std::size_t done, std::size_t total) { bar(done, total); });

  const std::vector<ScheduledProgram> programs =
      schedule_operations(job, allowance, bounds, files, file_of);
  std::vector<std::string> texts;
  for (const ScheduledFile& file : files) {
    const std::string text = read_text_file(file.path, "toolpath");
    texts.push_back(
        rewrite_feeds(text, file.format, file.lines, file.path, FeedRewriteOptions{file.gcode}));
  }

  // Everything is computed: write the programs, each whole.
  if (files.size() > 1) std::filesystem::create_directories(options.out);
  for (std::size_t f = 0; f < files.size(); ++f) write_file_atomically(files[f].target, texts[f]);

  print_schedule_report(out, limit, job, programs, files);
  return 0;
}

}  // namespace cwe::app
