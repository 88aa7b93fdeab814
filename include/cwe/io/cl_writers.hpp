#pragma once
// The per-cutter-location outputs of a job, as sinks of its run (cwe/job/run.hpp):
// engagement.csv, engagement.jsonl and forces.csv (EngagementFiles), the engagement maps, the
// path plot and the force curves (Figures), each written whole or not at all
// (docs/simulate.md, "Outputs"). Lengths in mm, or inches on request (ReportUnit).

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/io/atomic_file.hpp"
#include "cwe/io/cl_sink.hpp"
#include "cwe/io/engagement_plot.hpp"

namespace cwe {

// The unit of the lengths the per-CL files and the terminal report give (--report-units).
struct ReportUnit {
  double mm = 1.0;         // mm per unit
  int extra_decimals = 0;  // written with this many more decimals than mm
  std::string name = "mm";
  // "mm" or "" (millimetres) or "in" (inches).
  static ReportUnit of(const std::string& units);
  // `length` mm in this unit; `area` mm² in its square.
  double length(double mm_value) const { return mm_value / mm; }
  double area(double mm2_value) const { return mm2_value / (mm * mm); }
  // A CSV header written for mm with "mm" made this unit's name.
  std::string header(std::string mm_header) const;
};

extern const char* const kForcesCsvHeader;

// One forces.csv row (tool frame; the workpiece-frame means, the chip and the feed after the
// required columns); lengths, feed per tooth, chip and feed rate in `unit`.
std::string forces_csv_row(std::size_t k, const ClPoint& cl, std::size_t operation, int tool,
                           double feed_rate, const ClForces& f, const ReportUnit& unit = {});

// engagement.csv's header (for mm) and one row: lengths in `unit`.
extern const char* const kEngagementCsvHeader;
std::string engagement_csv_row(std::size_t k, const ClPoint& cl, const ToolState& state,
                               const EngagementMap& map, std::size_t operation, int tool,
                               const ReportUnit& unit);
// One engagement.jsonl line: the engaged discs and rings, angles in degrees, heights and radii in
// `unit`.
std::string engagement_jsonl_line(std::size_t k, const ClPoint& cl, const EngagementMap& map,
                                  const ReportUnit& unit);

// Which CLs get a map figure: every:N, cl:i,j,… (indices from 0), none, or (empty) about ten
// spread over the path: in each tenth of the CLs, its first engaged one.
struct MapChoice {
  std::size_t every = 0;        // 0: none by period
  std::vector<std::size_t> cl;  // sorted
  bool engaged_only = false;    // the default: each period's first engaged CL
  bool due = false;             // (default) a period began and has no map yet
  bool chosen(std::size_t k, bool engaged) {
    if (engaged_only) {
      due = due || k % every == 0;
      if (!due || !engaged) return false;
      due = false;
      return true;
    }
    return (every > 0 && k % every == 0) || std::binary_search(cl.begin(), cl.end(), k);
  }
};

// An output folder (maps/, force_curves/) written whole or not at all: files go to a temporary
// folder that replaces <out>/<name> only when the job has finished.
class OutputFolder {
 public:
  OutputFolder(const std::filesystem::path& out, const std::string& name);
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder();
  void write(const std::string& name, std::string_view bytes);
  // Replaces <out>/<name> with what was written; InputError when it cannot.
  void commit();
  const std::filesystem::path& path() const { return target_; }  // <out>/<name>

 private:
  std::filesystem::path target_, temporary_;
  bool committed_ = false;
};

// engagement.csv, engagement.jsonl and (with forces) forces.csv in `folder`, streamed to
// temporary files that replace the targets when committed.
class EngagementFiles : public ClSink {
 public:
  EngagementFiles(const std::filesystem::path& folder, bool forces, const ReportUnit& unit);
  void add(const ClResult& r) override;
  void finish();  // writes what is buffered
  // Puts the files in place; returns their paths.
  std::vector<std::filesystem::path> commit();

 private:
  void flush(bool force);  // appends the buffers from about a megabyte on (or when `force`)

  ReportUnit unit_;
  AtomicFileWriter csv_, jsonl_;
  std::optional<AtomicFileWriter> forces_;
  std::string csv_block_, jsonl_block_, forces_block_;
};

// maps/ (the chosen CLs' engagement maps, and path.png along the job) and, with forces,
// force_curves/ (the chosen CLs' force-versus-angle curves) in `folder`.
class Figures : public ClSink {
 public:
  // A CL's figures are drawn and written on another thread while the job goes on (the sink runs
  // in order, and a figure held the whole pipeline up while it was drawn and synced); finish()
  // and commit() wait for them, and report the first that failed.
  // The path plot keeps at most about this many CLs (40 bytes each): of a job with more, every
  // k-th (the plot is about a thousand pixels wide).
  static constexpr std::size_t kPathPoints = 1'000'000;
  // `cl_count`: the job's CLs, for the path plot's stride.
  Figures(const std::filesystem::path& folder, MapChoice maps, MapChoice curves, bool forces,
          std::size_t cl_count);
  ~Figures() override;
  Figures(const Figures&) = delete;
  Figures& operator=(const Figures&) = delete;
  bool wants_curve(std::size_t index, bool engaged) override;
  void add(const ClResult& r) override;
  void finish(const std::string& title);  // draws the path plot
  // Puts the folders in place once their figures are written; returns their paths.
  std::vector<std::filesystem::path> commit();
  std::size_t maps_written() const { return maps_written_; }
  std::size_t curves_written() const { return curves_written_; }

 private:
  MapChoice maps_, curves_;
  OutputFolder map_folder_;
  std::optional<OutputFolder> curve_folder_;
  std::vector<PathPlotPoint> along_;
  std::size_t path_stride_ = 1;  // every path_stride_-th CL in along_
  bool curve_ = false;           // the CL being added asked for its curve
  std::size_t maps_written_ = 0, curves_written_ = 0;
  struct Drawing;                    // the figures being drawn
  std::unique_ptr<Drawing> drawing_;
};

}  // namespace cwe
