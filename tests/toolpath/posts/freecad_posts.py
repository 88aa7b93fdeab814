# The FreeCAD 0.20 CAM job behind freecad_linuxcnc.ngc, freecad_grbl.nc and freecad_fanuc.nc
# (tests/toolpath/gcode_posts_test.cpp): a 20 x 10 x 5 block profiled outside, 2.5 mm step-downs,
# with tool 1 of FreeCAD's Default library (5 mm end mill), posted with FreeCAD's own LinuxCNC,
# grbl and Fanuc posts. Run in this folder with: freecadcmd freecad_posts.py (each program's
# output-time comment was then blanked).
import importlib
import os

import FreeCAD, Part
import PathScripts.PathJob as PathJob
import PathScripts.PathProfile as PathProfile
import PathScripts.PathToolBit as PathToolBit

doc = FreeCAD.newDocument("cwe")
obj = doc.addObject("Part::Feature", "Part")
obj.Shape = Part.makeBox(20, 10, 5)
doc.recompute()
job = PathJob.Create("Job", [obj], None)
doc.recompute()
tc = job.Tools.Group[0]
tc.Tool = PathToolBit.Factory.CreateFrom(
    "/usr/share/freecad/Mod/Path/Tools/Bit/5mm_Endmill.fctb", "Endmill")
tc.ToolNumber = 1
# FreeCAD 0.20's Fanuc post still asks the tool for the legacy ToolType (taps are rigid tapped).
tc.Tool.addProperty("App::PropertyString", "ToolType")
tc.Tool.ToolType = "EndMill"
tc.HorizFeed = 10  # mm/s: 600 mm/min
tc.VertFeed = 3
tc.SpindleSpeed = 10000
profile = PathProfile.Create("Profile")
profile.ToolController = tc
profile.setExpression("StepDown", None)
profile.StepDown.Value = 2.5
profile.Side = "Outside"
doc.recompute()
for name, out, args in [("linuxcnc", "freecad_linuxcnc.ngc", "--no-show-editor --precision 3"),
                        ("grbl", "freecad_grbl.nc", "--no-show-editor --precision 3"),
                        # The Fanuc post writes the file's name as the program's first line: named
                        # as the post expects, by its program number.
                        ("fanuc", "O1001", "--no-show-editor")]:
    post = importlib.import_module("PathScripts.post.%s_post" % name)
    post.export([tc, profile], out, args)
    print("wrote", out)
os.replace("O1001", "freecad_fanuc.nc")
