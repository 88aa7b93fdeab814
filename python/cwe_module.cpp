// The compiled part of the `cwe` Python package (python/cwe/__init__.py wraps it): a job, its
// run with every cutter location's engagement and forces kept in columns, the in-process stock
// as a mesh, and tools. Errors in the user's input raise cwe.InputError with file, line and
// column; the run releases the GIL.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/io/cl_sink.hpp"
#include "cwe/io/step.hpp"
#include "cwe/job/job.hpp"
#include "cwe/job/run.hpp"
#include "cwe/job/summary.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/dexel/dexel_mesh.hpp"

namespace py = pybind11;

namespace cwe::python {
namespace {

double degrees(double radians) { return radians * 180.0 / kPi; }

// The columns of engagement.csv and forces.csv, and every CL's discs and rings.
struct Columns : ClSink {
  std::map<std::string, std::vector<double>> engagement;
  std::vector<std::string> motion;
  std::map<std::string, std::vector<double>> forces;
  std::vector<EngagementMap> maps;

  void add(const ClResult& r) override {
    auto& e = engagement;
    e["cl"].push_back(static_cast<double>(r.index));
    e["move"].push_back(r.cl.move + 1);
    e["line"].push_back(r.cl.line);
    for (int a = 0; a < 3; ++a) {
      e[std::string(1, "xyz"[a])].push_back(r.cl.position[a]);
      e[std::string(1, "ijk"[a])].push_back(r.cl.axis[a]);
      e[std::string("feed_") + "xyz"[a]].push_back(r.cl.feed_direction[a]);
    }
    e["engaged"].push_back(r.map.engaged ? 1.0 : 0.0);
    e["phi_entry_deg"].push_back(degrees(r.map.phi_entry));
    e["phi_exit_deg"].push_back(degrees(r.map.phi_exit));
    e["axial_depth_mm"].push_back(r.map.axial_depth);
    e["area_mm2"].push_back(r.map.area);
    e["u"].push_back(r.cl.u);
    e["path_mm"].push_back(r.cl.path_length);
    e["operation"].push_back(static_cast<double>(r.operation + 1));
    e["tool"].push_back(r.tool);
    motion.emplace_back(to_string(r.state.motion));
    maps.push_back(r.map);
    if (r.forces == nullptr) return;
    const ClForces& f = *r.forces;
    auto& c = forces;
    c["cl"].push_back(static_cast<double>(r.index));
    c["move"].push_back(r.cl.move + 1);
    c["feed_per_tooth_mm"].push_back(f.feed_per_tooth);
    for (int a = 0; a < 3; ++a) {
      c[std::string("mean_f") + "xyz"[a] + "_n"].push_back(f.mean_force[a]);
      c[std::string("peak_f") + "xyz"[a] + "_n"].push_back(f.peak_force[a]);
      c[std::string("mean_world_f") + "xyz"[a] + "_n"].push_back(f.mean_force_world[a]);
      c[std::string("peak_world_f") + "xyz"[a] + "_n"].push_back(f.peak_force_world[a]);
    }
    c["peak_resultant_n"].push_back(f.peak_resultant);
    c["mean_torque_nm"].push_back(f.mean_torque);
    c["peak_torque_nm"].push_back(f.peak_torque);
    c["mean_power_w"].push_back(f.mean_power);
    c["line"].push_back(r.cl.line);
    c["operation"].push_back(static_cast<double>(r.operation + 1));
    c["feed_mm_min"].push_back(r.feed_rate);
    c["spindle_rpm"].push_back(f.spindle_speed);
    c["max_chip_mm"].push_back(f.max_chip);
    c["tool"].push_back(r.tool);
  }
};

// A finished run: the columns, the stock and the summary.
struct Run {
  std::shared_ptr<Columns> columns;
  std::shared_ptr<JobResult> result;
  std::string summary;
  double deviation = 0.0;  // a B-rep stock's tessellation, mm (s/10, as stock.stl)
};

py::dict arrays(const std::map<std::string, std::vector<double>>& columns) {
  py::dict out;
  for (const auto& [name, values] : columns) {
    out[py::str(name)] = py::array_t<double>(static_cast<py::ssize_t>(values.size()),
                                              values.data());
  }
  return out;
}

py::list intervals(const std::vector<Interval>& phi) {
  py::list out;
  for (const Interval& i : phi) out.append(py::make_tuple(degrees(i.lo), degrees(i.hi)));
  return out;
}

// `progress` (None, or a callable taking moves done and moves in all) is called, holding the
// GIL, each time another percent of the moves is done.
Run run(Job job, bool engagement, const py::object& progress) {
  const auto started = std::chrono::steady_clock::now();
  PreparedJob prepared = prepare_job(job);
  JobStock stock = make_job_stock(prepared);
  auto columns = std::make_shared<Columns>();
  ClSink* const sinks[] = {columns.get()};
  std::shared_ptr<JobResult> result;
  int shown = -1;
  const Progress report = [&](std::size_t done, std::size_t total) {
    if (progress.is_none() || total == 0) return;
    const int percent = static_cast<int>(100 * done / total);
    if (percent == shown) return;
    shown = percent;
    py::gil_scoped_acquire acquire;
    progress(done, total);
  };
  const auto simulating = std::chrono::steady_clock::now();
  {
    py::gil_scoped_release release;
    result = std::make_shared<JobResult>(
        run_job(prepared, std::move(stock), RunOptions{engagement}, sinks, report));
  }
  const auto done = std::chrono::steady_clock::now();
  JobSummary extras;
  extras.stock = job.stock;
  extras.engagement = engagement;
  // No closing stage: the stock is contoured when asked for (Run.stock_mesh).
  extras.set_up_seconds = std::chrono::duration<double>(simulating - started).count();
  extras.simulation_seconds = std::chrono::duration<double>(done - simulating).count();
  return Run{columns, result, job_summary(prepared, *result, extras),
             step_tessellation(prepared.simulation, false)};
}

}  // namespace
}  // namespace cwe::python

PYBIND11_MODULE(_cwe, m) {
  using namespace cwe;
  using namespace cwe::python;
  m.doc() = "cutter-workpiece engagement: the compiled part of the cwe package";

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // The library names a setting by its command-line option; here it is a Job attribute.
      SourceLocation where = e.location();
      std::string text = e.what();
      if (where.source.rfind("--", 0) == 0 && where.line == 0) {
        where.source = where.source.substr(2);
        std::replace(where.source.begin(), where.source.end(), '-', '_');
        text = where.source + ": error: " + e.message();
      }
      py::object error = py::reinterpret_borrow<py::object>(input_error.ptr())(text);
      error.attr("file") = where.source;
      error.attr("line") = e.location().line;
      error.attr("column") = e.location().column;
      error.attr("reason") = e.message();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });

  py::class_<Operation>(m, "Operation")
      .def(py::init<std::string, std::string>(), py::arg("tool") = "", py::arg("path") = "")
      .def_readwrite("tool", &Operation::tool)
      .def_readwrite("path", &Operation::path);

  py::class_<Job>(m, "Job")
      .def(py::init<>())
      .def_readwrite("stock", &Job::stock)
      .def_readwrite("tool", &Job::tool)
      .def_readwrite("path", &Job::path)
      .def_readwrite("operations", &Job::operations)
      .def_readwrite("tools", &Job::tools)
      .def_readwrite("tool_for_all", &Job::tool_for_all)
      .def_readwrite("tool_units", &Job::tool_units)
      .def_readwrite("start", &Job::start)
      .def_readwrite("tool_change", &Job::tool_change)
      .def_readwrite("subroutine_path", &Job::subroutine_path)
      .def_readwrite("machine", &Job::machine)
      .def_readwrite("units", &Job::units)
      .def_readwrite("workpiece", &Job::workpiece)
      .def_readwrite("resolution", &Job::resolution)
      .def_readwrite("facet", &Job::facet)
      .def_readwrite("tolerance", &Job::tolerance)
      .def_readwrite("threads", &Job::threads)
      .def_readwrite("cl_step", &Job::cl_step)
      .def_readwrite("forces", &Job::forces)
      .def_readwrite("spindle", &Job::spindle)
      .def_readwrite("feed", &Job::feed)
      .def_readwrite("flutes", &Job::flutes)
      .def_readwrite("helix", &Job::helix)
      .def_readwrite("force_step", &Job::force_step)
      .def_readwrite("runout", &Job::runout);

  py::class_<Run>(m, "Run")
      .def_property_readonly("engagement_columns",
                             [](const Run& r) { return arrays(r.columns->engagement); })
      .def_property_readonly("motion", [](const Run& r) { return r.columns->motion; })
      .def_property_readonly("forces_columns",
                             [](const Run& r) { return arrays(r.columns->forces); })
      .def_property_readonly("summary_json", [](const Run& r) { return r.summary; })
      .def(
          "discs",
          [](const Run& r, std::size_t cl) {
            const auto& maps = r.columns->maps;
            if (cl >= maps.size()) {
              throw py::index_error("cutter location " + std::to_string(cl) + " of " +
                                    std::to_string(maps.size()));
            }
            py::list discs, rings;
            for (const DiscEngagement& d : maps[cl].discs) {
              if (!d.phi.empty()) discs.append(py::make_tuple(d.z0, d.z1, intervals(d.phi)));
            }
            for (const RingEngagement& ring : maps[cl].rings) {
              if (!ring.phi.empty()) {
                rings.append(py::make_tuple(ring.r0, ring.r1, intervals(ring.phi)));
              }
            }
            return py::make_tuple(discs, rings);
          },
          py::arg("cl"))
      .def(
          "stock_mesh",
          [](const Run& r, int stride) {
            // The rays contoured at `stride`, the mesh workpiece itself, or the solid
            // tessellated within s/10 (`stride` applies to rays only).
            const TriangleMesh mesh = r.result->stock  ? dexel_mesh(*r.result->stock, stride)
                                      : r.result->mesh ? r.result->mesh->mesh()
                                                       : tessellate(*r.result->brep, r.deviation);
            py::array_t<double> v({static_cast<py::ssize_t>(mesh.vertices.size()),
                                   static_cast<py::ssize_t>(3)});
            py::array_t<int> f({static_cast<py::ssize_t>(mesh.triangles.size()),
                                static_cast<py::ssize_t>(3)});
            auto vv = v.mutable_unchecked<2>();
            auto ff = f.mutable_unchecked<2>();
            for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
              for (int a = 0; a < 3; ++a) {
                vv(static_cast<py::ssize_t>(i), a) = mesh.vertices[i][a];
              }
            }
            for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
              for (int a = 0; a < 3; ++a) {
                ff(static_cast<py::ssize_t>(i), a) = mesh.triangles[i][static_cast<std::size_t>(a)];
              }
            }
            return py::make_tuple(v, f);
          },
          py::arg("stride") = 1);

  m.def("_run", &run, py::arg("job"), py::arg("engagement") = true,
        py::arg("progress") = py::none());

  m.def(
      "_tool_profile",
      [](const std::string& spec, int samples) {
        const Cutter cutter = cutter_from_spec(spec, SourceLocation{"tool"});
        const Profile& profile = cutter.profile();
        const double h = profile.height();
        py::array_t<double> rho(samples), z(samples);
        auto rr = rho.mutable_unchecked<1>();
        auto zz = z.mutable_unchecked<1>();
        for (int i = 0; i < samples; ++i) {
          const double height = h * i / (samples - 1);
          zz(i) = height;
          rr(i) = profile.radius_at(height);
        }
        return py::make_tuple(rho, z, cutter.name(), cutter.diameter());
      },
      py::arg("spec"), py::arg("samples") = 200);
}
