"""Checks that ParaView loads the installed BoneMachining plugin found through PV_PLUGIN_PATH.

usage: PV_PLUGIN_PATH=PREFIX/lib/paraview-plugins/BoneMachining pvbatch TestInstalledPlugin.py

Nothing is loaded by path: the "BM Tool" source must exist because ParaView found the plugin in
PV_PLUGIN_PATH at start-up, and it must build a non-empty reamer surface. Exits non-zero on failure.
"""
import sys

from paraview.simple import *  # noqa: F401,F403 (defines one function per loaded source)

if "BMTool" not in globals():
    print("FAIL: ParaView did not load the plugin from PV_PLUGIN_PATH (no BMTool source)")
    sys.exit(1)
tool = globals()["BMTool"]()
tool.ToolType = "Glenoid reamer"
tool.UpdatePipeline()
points = tool.GetDataInformation().GetNumberOfPoints()
if points == 0:
    print("FAIL: the installed plugin's reamer surface is empty")
    sys.exit(1)
print("installed plugin: ok (reamer surface of %d points)" % points)
