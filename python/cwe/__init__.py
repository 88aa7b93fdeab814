"""Cutter-workpiece engagement in milling, from Python.

    import cwe
    job = cwe.Job(stock="box:0,0,-30,100,60,0", tool="flat:10,30", path="pocket.ngc",
                  resolution=0.1)
    run = cwe.run(job, forces="al7075-t6-carbide")
    run.engagement          # structured NumPy array: the columns of engagement.csv
    run.discs(cl)           # engaged discs and bottom rings of one cutter location
    run.forces              # structured NumPy array: the columns of forces.csv
    v, f = run.stock_mesh() # the machined stock: vertices, triangles
    cwe.Tool("bull:10,2").profile()

Lengths are in mm and angles in degrees, as in the files `cwe simulate` writes (docs/python.md).
Errors in the input raise cwe.InputError (a ValueError) with .file, .line, .column and .reason.
"""

import json
import sys

import numpy as np

from . import _cwe
from ._cwe import InputError, Operation

__all__ = ["Job", "Operation", "Run", "Tool", "InputError", "run"]

_JOB_SETTINGS = [
    "stock", "tool", "path", "operations", "tools", "tool_for_all", "tool_units", "start",
    "tool_change", "subroutine_path", "machine", "units", "workpiece", "resolution", "facet",
    "tolerance", "threads",
    "cl_step", "forces", "spindle", "feed", "flutes", "helix", "force_step", "runout",
]

# The columns of engagement.csv and forces.csv, in their order.
ENGAGEMENT_COLUMNS = [
    "cl", "move", "line", "x", "y", "z", "i", "j", "k", "feed_x", "feed_y", "feed_z", "engaged",
    "phi_entry_deg", "phi_exit_deg", "axial_depth_mm", "area_mm2", "u", "path_mm", "motion",
    "operation", "tool",
]
FORCE_COLUMNS = [
    "cl", "move", "feed_per_tooth_mm", "mean_fx_n", "mean_fy_n", "mean_fz_n", "peak_fx_n",
    "peak_fy_n", "peak_fz_n", "peak_resultant_n", "mean_torque_nm", "peak_torque_nm",
    "mean_power_w", "line", "operation", "feed_mm_min", "spindle_rpm", "max_chip_mm",
    "mean_world_fx_n", "mean_world_fy_n", "mean_world_fz_n", "peak_world_fx_n",
    "peak_world_fy_n", "peak_world_fz_n", "tool",
]
_WHOLE = {"cl", "move", "line", "engaged", "operation", "tool"}


class Job(_cwe.Job):
    """A job: the settings of `cwe simulate` (docs/simulate.md) as keyword arguments."""

    def __init__(self, **settings):
        super().__init__()
        self.update(**settings)

    def update(self, **settings):
        for name, value in settings.items():
            if name not in _JOB_SETTINGS:
                raise TypeError(f"Job has no setting {name!r}; the settings are "
                                + ", ".join(_JOB_SETTINGS))
            if name == "operations":
                value = [o if isinstance(o, Operation) else Operation(**o) for o in value]
            setattr(self, name, value)
        return self

    def copy(self):
        return Job(**{name: getattr(self, name) for name in _JOB_SETTINGS})


def _structured(columns, order, motion=None):
    names = [n for n in order if n in columns or (n == "motion" and motion is not None)]
    fields = []
    for n in names:
        if n == "motion":
            fields.append(np.array(motion, dtype="U10"))
        elif n in _WHOLE:
            fields.append(np.asarray(columns[n]).astype(np.int64))
        else:
            fields.append(np.asarray(columns[n]))
    if not fields:
        return np.zeros(0, dtype=[(n, "f8") for n in order if n != "motion"])
    return np.rec.fromarrays(fields, names=names)


class Run:
    """A finished run of a job."""

    def __init__(self, raw):
        self._raw = raw

    @property
    def engagement(self):
        """One record per cutter location: the columns of engagement.csv."""
        return _structured(self._raw.engagement_columns, ENGAGEMENT_COLUMNS, self._raw.motion)

    @property
    def forces(self):
        """One record per cutter location (with forces): the columns of forces.csv."""
        return _structured(self._raw.forces_columns, FORCE_COLUMNS)

    @property
    def summary(self):
        """summary.json as a dict (without "stock_mesh": no stock.stl is written)."""
        return json.loads(self._raw.summary_json)

    def discs(self, cl):
        """The engaged discs [(z0, z1, [(entry, exit), ...]), ...] and bottom rings
        [(r0, r1, [(entry, exit), ...]), ...] of cutter location `cl` (heights and radii in mm,
        angles in degrees)."""
        return self._raw.discs(cl)

    def stock_mesh(self, stride=1):
        """The machined stock as a closed mesh: vertices (n × 3, mm) and triangles (m × 3)."""
        return self._raw.stock_mesh(stride)


def _interactive():
    return sys.stderr.isatty() or "ipykernel" in sys.modules


def _progress_bar(done, total):
    """A one-line bar on standard error, redrawn in place."""
    percent = 100 * done // total
    filled = percent * 40 // 100
    sys.stderr.write(f"\rremoving material [{'#' * filled}{' ' * (40 - filled)}] {percent:3d}%  "
                     f"move {done}/{total}")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def run(job, engagement=True, progress=None, **settings):
    """Runs `job` (a Job, or the settings of one), with `settings` overriding its own.

    `progress`: None (the default) shows a bar on standard error in a terminal or a notebook;
    False shows none; a callable is called with (moves done, moves in all) at each percent. The
    GIL is released while the job runs."""
    if not isinstance(job, Job):
        job = Job(**job) if isinstance(job, dict) else job
    job = job.copy().update(**settings) if settings else job.copy()
    if progress is None:
        progress = _progress_bar if _interactive() else False
    return Run(_cwe._run(job, engagement, progress if progress else None))


class Tool:
    """A cutter from a tool specification (`cwe tool --help`)."""

    def __init__(self, spec):
        self.spec = spec
        _, _, self.name, self.diameter = _cwe._tool_profile(spec, 2)

    def profile(self, samples=200):
        """The profile sampled along the axis: radius ρ(z) and height z, mm."""
        rho, z, _, _ = _cwe._tool_profile(self.spec, samples)
        return rho, z
