# The FreeCAD 0.20 CAM job behind freecad_pocket_profile.ngc (tests/engagement/
# engagement_program_test.cpp): an 80 × 50 × 20 part with 6 mm rounded corners and a 40 × 20 × 9 pocket,
# a 5 mm end mill, a pocket in 3 mm step-downs and an outside profile in 4 mm step-downs, posted
# for LinuxCNC. Run in this folder with: freecadcmd freecad_pocket_profile.py (the program's
# output-time comment was then blanked).
import FreeCAD, Part
import PathScripts.PathJob as PathJob
import PathScripts.PathProfile as PathProfile
import PathScripts.PathPocketShape as PathPocketShape
import PathScripts.PathAdaptive as PathAdaptive
import PathScripts.PathToolController as PathToolController
import importlib

out = "freecad_pocket_profile.ngc"
doc = FreeCAD.newDocument("cwe")
block = Part.makeBox(80, 50, 20)
pocket = Part.makeBox(40, 20, 9, FreeCAD.Vector(20, 15, 11))
part = block.cut(pocket)
# round the outer vertical edges so the contour has arcs
edges = [e for e in part.Edges if abs(e.Vertexes[0].Point.z - e.Vertexes[1].Point.z) > 19.9
         and (abs(e.Vertexes[0].Point.x) < 1e-6 or abs(e.Vertexes[0].Point.x - 80) < 1e-6)]
part = part.makeFillet(6, edges)
obj = doc.addObject("Part::Feature", "Part")
obj.Shape = part
doc.recompute()

job = PathJob.Create("Job", [obj], None)
doc.recompute()
tc = job.Tools.Group[0]
print("tool", tc.Tool.Label, tc.Tool.Diameter, "stock", job.Stock.Shape.BoundBox)
tc.HorizFeed = 600
tc.VertFeed = 200
tc.SpindleSpeed = 10000

faces = [f"Face{i+1}" for i, f in enumerate(obj.Shape.Faces)
         if abs(f.normalAt(0, 0).z - 1) < 1e-6 and abs(f.CenterOfMass.z - 11) < 1e-6]
print("pocket floor", faces)
pk = PathPocketShape.Create("Pocket")
pk.Base = [(obj, faces)]
pk.setExpression("StepDown", None)
pk.StepDown.Value = 3.0
pk.StepOver = 50
doc.recompute()

pr = PathProfile.Create("Profile")
pr.setExpression("StepDown", None)
pr.StepDown.Value = 4.0
pr.Side = "Outside"
doc.recompute()

post = importlib.import_module("PathScripts.post.linuxcnc_post")
objects = [tc, pk, pr]
post.export(objects, out, "--no-show-editor --precision 4")
print("wrote", out)
