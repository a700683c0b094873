# BMInstall: `cmake --install` into a temporary prefix; the installed bmsim finds its resources in
# <prefix>/share/BoneMachining (not the source tree) and runs a built-in scene from there, and
# ParaView loads the installed plugin from PV_PLUGIN_PATH (TestInstalledPlugin.py).
#   cmake -DBUILD_DIR=... -DWORK_DIR=... -DPVBATCH=... -DSCRIPT=... -P TestInstall.cmake
foreach(v BUILD_DIR WORK_DIR PVBATCH SCRIPT)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "TestInstall.cmake needs -D${v}=")
  endif()
endforeach()
set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}):\n${out}\n${err}")
endif()
foreach(f bin/bmsim share/BoneMachining/Scenes/glenoid.json share/BoneMachining/Benchmark/bench.csv
          lib/paraview-plugins/BoneMachining/BoneMachining.so)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "the install has no ${f}")
  endif()
endforeach()

# The installed bmsim names the installed resource folder, with no environment to guide it.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=BM_RESOURCE_DIR ${prefix}/bin/bmsim --version
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "resources: ${prefix}/share/BoneMachining")
  message(FATAL_ERROR "installed bmsim --version (${rc}) does not name the installed resources:\n${out}${err}")
endif()

# A built-in scene read from the installed copy: the drilling scene is in code, so run the installed
# scene list's error path and the drilling run from the prefix with the source tree out of reach
# (a scene file that exists only in the installed folder must be found).
file(WRITE ${prefix}/share/BoneMachining/Scenes/installcheck.json
     "{\"name\": \"installcheck\", \"voxmap_resolution\": 32, \"shell_resolution\": 64}\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=BM_RESOURCE_DIR
                        ${prefix}/bin/bmsim run installcheck --out ${WORK_DIR}/run
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK_DIR}/run/summary.json)
  message(FATAL_ERROR "installed bmsim run installcheck failed (${rc}):\n${out}\n${err}")
endif()

# ParaView loads the installed plugin from PV_PLUGIN_PATH and builds a tool from it.
execute_process(COMMAND ${CMAKE_COMMAND} -E env
                        PV_PLUGIN_PATH=${prefix}/lib/paraview-plugins/BoneMachining
                        ${PVBATCH} --force-offscreen-rendering ${SCRIPT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "installed plugin: ok")
  message(FATAL_ERROR "pvbatch with the installed plugin failed (${rc}):\n${out}\n${err}")
endif()
message(STATUS "install: ok (${prefix})")
