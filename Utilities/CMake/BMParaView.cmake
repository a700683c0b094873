# BMParaView.cmake - finds ParaView 5.11 (Debian's paraview-dev) and the VTK it carries.
#
# include(BMParaView) in every directory that uses ParaView, VTK or Qt targets: imported targets
# are directory-scoped, so a directory whose parent did not find ParaView finds it here. The
# include is a no-op where the targets are already visible.
#
# Debian's ParaView config fails on optional third parties unless they are found first and the
# components are named (Docs/Platform.md section 2): HDF5 (C, HL, parallel), GLEW, LibXml2,
# Boost, NetCDF.
if(TARGET ParaView::RemotingServerManager AND TARGET Qt5::Widgets)
  return()
endif()

# Two packages Debian's paraview-dev config needs without depending on them: say so plainly
# instead of failing deep inside ParaView's config.
find_package(Qt5OpenGL QUIET)
if(NOT Qt5OpenGL_FOUND)
  message(FATAL_ERROR "ParaView's config needs Qt5OpenGL: install libqt5opengl5-dev")
endif()
find_file(BM_PARAVIEW_PYTHON_INIT paraview/__init__.py
  PATHS /usr/lib/python3/dist-packages NO_DEFAULT_PATH)
if(NOT BM_PARAVIEW_PYTHON_INIT)
  message(FATAL_ERROR "ParaView's config needs its Python modules: install python3-paraview")
endif()

set(HDF5_PREFER_PARALLEL ON)
find_package(HDF5 REQUIRED COMPONENTS C HL)
find_package(GLEW REQUIRED)
find_package(LibXml2 REQUIRED)
find_package(Boost)
set(_bm_pv_prefix_guess "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/paraview-5.11")
if(EXISTS "${_bm_pv_prefix_guess}/vtk/FindNetCDF.cmake")
  list(APPEND CMAKE_MODULE_PATH "${_bm_pv_prefix_guess}/vtk")
endif()
find_package(NetCDF)

find_package(ParaView 5.11 REQUIRED
  COMPONENTS
    RemotingCore RemotingServerManager RemotingApplication RemotingViews VTKExtensionsCore
    pqCore pqComponents pqApplicationComponents)
find_package(Qt5 REQUIRED COMPONENTS Core Gui Widgets)

# ParaView's own executables, for the tests that load the plugin.
find_program(BM_PVPYTHON_EXECUTABLE pvpython HINTS "${ParaView_PREFIX_PATH}/bin")
find_program(BM_PVBATCH_EXECUTABLE pvbatch HINTS "${ParaView_PREFIX_PATH}/bin")
find_program(BM_PARAVIEW_EXECUTABLE paraview HINTS "${ParaView_PREFIX_PATH}/bin")
# Tests that render run under a private Xvfb that picks its own display (Testing/with-xvfb.sh).
find_program(BM_XVFB_EXECUTABLE Xvfb)
if(BM_XVFB_EXECUTABLE)
  get_filename_component(_bm_with_xvfb "${CMAKE_CURRENT_LIST_DIR}/../../Testing/with-xvfb.sh"
    ABSOLUTE)
  set(BM_WITH_XVFB bash "${_bm_with_xvfb}")
endif()
