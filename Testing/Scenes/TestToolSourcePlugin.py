"""Loads the BoneMachining plugin in pvbatch and checks the "BM Tool" source (vtkBMToolSource).

usage: pvbatch --force-offscreen-rendering TestToolSourcePlugin.py PATH/TO/BoneMachining.so

Each tool's surface must be non-empty, have the tool's outer radius and axial extent as bounds
(Resolution is a multiple of 4, so the bounds are exact), carry outward normals and mark cutting
lips in the EdgeKind cell array. Exits non-zero on the first failed check.
"""
import math
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin

TOLERANCE_MM = 1e-6


def check(condition, message):
    if not condition:
        print("FAIL: " + message)
        sys.exit(1)


def check_tool(source, tool_type, radius_mm):
    source.ToolType = tool_type
    source.Resolution = 64
    source.UpdatePipeline()
    source.UpdatePipelineInformation()
    info = source.GetDataInformation()
    check(info.GetNumberOfPoints() > 0, "%s: no points" % tool_type)
    check(info.GetNumberOfCells() > 0, "%s: no cells" % tool_type)
    x0, x1, y0, y1, z0, z1 = info.GetBounds()
    for name, value, expected in (("x min", x0, -radius_mm), ("x max", x1, radius_mm),
                                  ("y min", y0, -radius_mm), ("y max", y1, radius_mm)):
        check(abs(value - expected) < TOLERANCE_MM,
              "%s: bounds %s = %.9g mm, expected %.9g" % (tool_type, name, value, expected))
    outer = source.GetProperty("OuterRadiusInfo")[0]
    check(abs(outer - radius_mm) < TOLERANCE_MM,
          "%s: OuterRadiusInfo %.9g, expected %.9g" % (tool_type, outer, radius_mm))
    check(z1 > z0, "%s: empty axial extent" % tool_type)
    axial = source.GetProperty("AxialRangeInfo")
    check(abs(z0 - axial[0]) < TOLERANCE_MM and abs(z1 - axial[1]) < TOLERANCE_MM,
          "%s: z bounds [%.9g, %.9g] differ from the tool's axial range [%.9g, %.9g]"
          % (tool_type, z0, z1, axial[0], axial[1]))

    surface = servermanager.Fetch(source)
    normals = surface.GetPointData().GetNormals()
    check(normals is not None, "%s: no point normals" % tool_type)
    # The point farthest from the axis lies on the periphery: its normal must point outward.
    points = surface.GetPoints()
    far, far_rho = 0, -1.0
    for i in range(surface.GetNumberOfPoints()):
        x, y, _ = points.GetPoint(i)
        rho = math.hypot(x, y)
        if rho > far_rho:
            far, far_rho = i, rho
    x, y, _ = points.GetPoint(far)
    nx, ny, _ = normals.GetTuple3(far)
    check((nx * x + ny * y) / far_rho > 0.5,
          "%s: normal at the periphery points inward or along the axis" % tool_type)
    kinds = surface.GetCellData().GetArray("EdgeKind")
    check(kinds is not None, "%s: no EdgeKind cell data" % tool_type)
    check(kinds.GetRange()[1] >= 1, "%s: no cutting lip marked in EdgeKind" % tool_type)
    print("%s: %d points, %d cells, bounds %s" % (tool_type, info.GetNumberOfPoints(),
                                                  info.GetNumberOfCells(), info.GetBounds()))


def main():
    check(len(sys.argv) == 2, "usage: TestToolSourcePlugin.py PLUGIN")
    LoadPlugin(sys.argv[1], remote=False, ns=globals())
    check("BMTool" in globals(), "the plugin did not define the BMTool source")
    source = globals()["BMTool"]()
    check_tool(source, "Twist drill", 1.25)  # the reference drill (Lee et al. 2012)
    check_tool(source, "Glenoid reamer", 18.25)  # 36.5 mm spherical reamer (Faieghi et al.)
    check_tool(source, "Spherical burr", 2.0)
    print("OK")


main()
