# The FreeCAD 0.20 CAM job behind freecad_two_tools.ngc (tests/app/cli_test.cpp,
# CliTools.FreeCadTwoToolProgram): a 60 × 40 × 15 block with a 30 × 16 × 6 pocket, cleared with
# tool 1 of FreeCAD's Default library (5 mm end mill) in 3 mm step-downs, then profiled outside
# with tool 4 (6 mm bull nose, 1.5 mm corner) in 5 mm step-downs, posted for LinuxCNC. Run in this
# folder with: freecadcmd freecad_two_tools.py (the program's output-time comment was then
# blanked). FreeCAD's feeds are in mm/s and its posts write mm/min.
import FreeCAD, Part
import PathScripts.PathJob as PathJob
import PathScripts.PathProfile as PathProfile
import PathScripts.PathPocketShape as PathPocketShape
import PathScripts.PathToolBit as PathToolBit
import PathScripts.PathToolController as PathToolController
import importlib

out = "freecad_two_tools.ngc"
bits = "/usr/share/freecad/Mod/Path/Tools/Bit/"
doc = FreeCAD.newDocument("cwe")
block = Part.makeBox(60, 40, 15)
pocket = Part.makeBox(30, 16, 6, FreeCAD.Vector(15, 12, 9))
obj = doc.addObject("Part::Feature", "Part")
obj.Shape = block.cut(pocket)
doc.recompute()

job = PathJob.Create("Job", [obj], None)
doc.recompute()
t1 = job.Tools.Group[0]
t1.Tool = PathToolBit.Factory.CreateFrom(bits + "5mm_Endmill.fctb", "Endmill")
t1.ToolNumber = 1
t1.HorizFeed = 10  # mm/s: 600 mm/min
t1.VertFeed = 3
t1.SpindleSpeed = 10000
faces = [f"Face{i+1}" for i, f in enumerate(obj.Shape.Faces)
         if abs(f.normalAt(0, 0).z - 1) < 1e-6 and abs(f.CenterOfMass.z - 9) < 1e-6]
pk = PathPocketShape.Create("Pocket")
pk.Base = [(obj, faces)]
pk.ToolController = t1
pk.setExpression("StepDown", None)
pk.StepDown.Value = 3.0
pk.StepOver = 50
doc.recompute()

pr = PathProfile.Create("Profile")
# Added after the operations exist: with two tool controllers FreeCAD's Create would ask which.
t2 = PathToolController.Create("TC: Bullnose",
                               PathToolBit.Factory.CreateFrom(bits + "6mm_Bullnose.fctb", "Bull"),
                               4)
job.Proxy.addToolController(t2)
t2.HorizFeed = 8
t2.VertFeed = 2.5
t2.SpindleSpeed = 8000
doc.recompute()
print("stock", job.Stock.Shape.BoundBox)
pr.ToolController = t2
pr.setExpression("StepDown", None)
pr.StepDown.Value = 5.0
pr.Side = "Outside"
doc.recompute()

print("tools", t1.Tool.Label, t1.ToolNumber, t2.Tool.Label, t2.ToolNumber)
post = importlib.import_module("PathScripts.post.linuxcnc_post")
post.export([t1, pk, t2, pr], out, "--no-show-editor --precision 3")
print("wrote", out)
