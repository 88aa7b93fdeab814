"""The cwe Python package (python/cwe): the slot's closed-form engagement through the API, the
arrays equal to the files `cwe simulate` writes for the same job, errors as exceptions.

Run by CTest (tests/CMakeLists.txt) with PYTHONPATH at build/python and CWE_BINARY the cwe
program."""

import csv
import os
import subprocess

import numpy as np
import pytest

import cwe

# A slot 3 mm deep with a 10 mm flat end mill, y = 10, from x = -10 to 60 through a 50 mm block.
SLOT = "G21 G90\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F300\nG1 X60 F600\nG0 Z5\nM2\n"
STOCK = "box:0,0,-10,50,20,0"
S = 0.25  # ray spacing, mm


@pytest.fixture
def slot(tmp_path):
    program = tmp_path / "slot.ngc"
    program.write_text(SLOT)
    return program


def slot_job(program):
    return cwe.Job(stock=STOCK, tool="flat:10,20", path=str(program), resolution=S)


def test_slot_engagement_is_the_closed_form(slot):
    run = cwe.run(slot_job(slot), forces="al7075-t6-carbide")
    e = run.engagement
    # Mid-slot (10 ≤ x ≤ 40 on the cutting move): full immersion, φ 0–180°, 3 mm deep. Within
    # s/(√2 R) = 0.25/(√2·5) rad ≈ 2° of the angles and within s of the depth.
    steady = e[(e["line"] == 5) & (e["x"] >= 10) & (e["x"] <= 40)]
    assert len(steady) > 50
    assert np.all(steady["engaged"] == 1)
    assert np.allclose(steady["phi_entry_deg"], 0.0, atol=2.1)
    assert np.allclose(steady["phi_exit_deg"], 180.0, atol=2.1)
    assert np.allclose(steady["axial_depth_mm"], 3.0, atol=S)
    # The discs of one of them cover 0–3 mm, each 0–180°.
    discs, rings = run.discs(int(steady["cl"][len(steady) // 2]))
    assert discs[0][0] == pytest.approx(0.0)
    assert discs[-1][1] == pytest.approx(3.0, abs=S)
    for z0, z1, intervals in discs:
        assert intervals[0][0] == pytest.approx(0.0, abs=2.1)
        assert intervals[-1][1] == pytest.approx(180.0, abs=2.1)
    # The removed volume is the slot's: 10 wide, 3 deep, 50 long, plus nothing else.
    assert run.summary["removed_volume_mm3"] == pytest.approx(1500.0, rel=1e-6)
    # The wall time in its stages: a run through the library contours nothing until asked.
    stages = run.summary["seconds_by_stage"]
    assert stages["set_up"] > 0.0 and stages["simulation"] > 0.0 and stages["closing"] == 0.0
    assert run.summary["seconds"] == pytest.approx(stages["set_up"] + stages["simulation"])
    v, f = run.stock_mesh()
    assert v.shape[1] == 3 and f.shape[1] == 3 and f.max() < len(v)
    # Forces where it cuts.
    forces = run.forces
    assert len(forces) == len(e)
    assert np.all(forces["peak_resultant_n"][steady["cl"]] > 10.0)


def test_brep_workpiece_engagement_and_stock(slot):
    # The same slot on the exact solid (the solid-model method): the angles to 0.1°, the depth
    # exactly, the removed volume exact, forces, and the solid's tessellation as the stock.
    job = cwe.Job(stock=STOCK, tool="flat:10,20", path=str(slot), resolution=S, workpiece="brep")
    run = cwe.run(job, forces="al7075-t6-carbide")
    e = run.engagement
    steady = e[(e["line"] == 5) & (e["x"] >= 10) & (e["x"] <= 40)]
    assert len(steady) > 50
    assert np.all(steady["engaged"] == 1)
    assert np.allclose(steady["phi_entry_deg"], 0.0, atol=0.1)
    assert np.allclose(steady["phi_exit_deg"], 180.0, atol=0.1)
    assert np.allclose(steady["axial_depth_mm"], 3.0, atol=1e-9)
    assert run.summary["workpiece"] == "brep"
    assert run.summary["removed_volume_mm3"] == pytest.approx(1500.0, rel=1e-6)
    assert np.all(run.forces["peak_resultant_n"][steady["cl"]] > 10.0)
    v, f = run.stock_mesh()
    assert v.shape[1] == 3 and f.shape[1] == 3 and f.max() < len(v)
    # The block less the slot: its bounds are the block's.
    assert np.allclose(v.min(axis=0), [0, 0, -10], atol=1e-6)
    assert np.allclose(v.max(axis=0), [50, 20, 0], atol=1e-6)


def read_csv(path):
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    return rows[0], rows[1:]


def test_arrays_equal_the_files_of_the_same_job(slot, tmp_path):
    out = tmp_path / "out"
    subprocess.run([os.environ["CWE_BINARY"], "simulate", "--stock", STOCK, "--tool",
                    "flat:10,20", "--path", str(slot), "--resolution", str(S), "--forces",
                    "al7075-t6-carbide", "--maps", "none", "--quiet", "--out", str(out)],
                   check=True, capture_output=True)
    run = cwe.run(slot_job(slot), forces="al7075-t6-carbide")
    for name, array in (("engagement.csv", run.engagement), ("forces.csv", run.forces)):
        header, rows = read_csv(out / name)
        assert list(array.dtype.names) == header
        assert len(rows) == len(array)
        for column, name_ in enumerate(header):
            values = [row[column] for row in rows]
            if array.dtype[name_].kind == "U":
                assert list(array[name_]) == values
                continue
            # The files print 3 to 6 decimals: equal within half of the last printed digit.
            decimals = max(len(v.split(".")[1]) if "." in v else 0 for v in values)
            assert np.allclose(array[name_], np.array(values, dtype=float),
                               atol=0.5 * 10.0 ** -decimals + 1e-12), name_


def test_errors_are_exceptions_with_their_place(tmp_path):
    bad = tmp_path / "bad.ngc"
    bad.write_text("G21 G90\nG1 X10 F300\nG1 X Y5\n")
    with pytest.raises(cwe.InputError) as error:
        cwe.run(cwe.Job(stock=STOCK, tool="flat:10", path=str(bad)))
    assert error.value.file == str(bad)
    assert error.value.line == 3
    assert error.value.column > 0
    assert isinstance(error.value, ValueError)
    with pytest.raises(cwe.InputError, match="diameter must be positive"):
        cwe.Tool("flat:-3")
    with pytest.raises(TypeError, match="stok"):
        cwe.Job(stok=STOCK)
    # A setting is named as the Job attribute it is.
    with pytest.raises(cwe.InputError, match="^stock: error: ") as error:
        cwe.run(cwe.Job(stock="box:0,0,0,1,1", tool="flat:3", path=str(bad)))
    assert error.value.file == "stock"
    with pytest.raises(cwe.InputError, match="^tool_change: error: "):
        cwe.run(cwe.Job(stock=STOCK, tool="flat:3", path=str(bad), tool_change="up"))


def test_tool_profile():
    rho, z = cwe.Tool("ball:6,20").profile(61)
    assert z[0] == 0.0 and z[-1] == pytest.approx(20.0)
    # A ball of radius 3: ρ = sqrt(z (6 − z)) up to z = 3, then 3.
    ball = z <= 3.0
    assert np.allclose(rho[ball], np.sqrt(z[ball] * (6.0 - z[ball])), atol=1e-9)
    assert np.allclose(rho[~ball], 3.0)


def test_progress_reaches_every_move(slot):
    calls = []
    cwe.run(slot_job(slot), progress=lambda done, total: calls.append((done, total)))
    assert calls[-1] == (4, 4)  # the slot program's four moves
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))
