# TestSkullScene.cmake - the built-in skull scene end to end from the command line: the real head
# CT of invesalius-examples imported and cropped, burred 1 mm into the vault. Run by ctest as
#   cmake -DBMSIM=<bmsim> -DWORK_DIR=<scratch folder> -P TestSkullScene.cmake
# Checks: exit 0, bone removed (a 2 mm burr 1 mm deep into the vault takes a few mm^3: the 5.2
# mm^3 of a 1 mm cap of a 2 mm ball where the voxmap's surface passes through the entry; the
# volume-conserving voxmap (bmVoxmapResampler.h) puts the vault's surface up to ~0.4 mm above
# that entry, picked on the CT's 1.5 mm slices, so up to the 8.7 mm^3 of a 1.4 mm cap), thrust and torque positive and below the
# quadrature of the fully engaged burr (the burr is never fully engaged at 1 mm).
cmake_minimum_required(VERSION 3.20)
set(out "${WORK_DIR}/skull")
file(REMOVE_RECURSE "${out}")
execute_process(COMMAND "${BMSIM}" run skull --no-report --out "${out}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
message(STATUS "bmsim run skull: exit ${rc}\n${stdout}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bmsim run skull failed (${rc}):\n${stderr}")
endif()
file(READ "${out}/summary.json" summary)
foreach(key removed_volume_mm3 thrust_N torque_Nmm reference_thrust_N reference_torque_Nmm)
  string(JSON ${key} GET "${summary}" ${key})
endforeach()
if(NOT (removed_volume_mm3 GREATER 1.0 AND removed_volume_mm3 LESS 8.7))
  message(FATAL_ERROR "removed volume ${removed_volume_mm3} mm^3 outside (1, 8.7)")
endif()
if(NOT (thrust_N GREATER 0 AND thrust_N LESS reference_thrust_N))
  message(FATAL_ERROR "thrust ${thrust_N} N outside (0, ${reference_thrust_N})")
endif()
if(NOT (torque_Nmm GREATER 0 AND torque_Nmm LESS reference_torque_Nmm))
  message(FATAL_ERROR "torque ${torque_Nmm} N mm outside (0, ${reference_torque_Nmm})")
endif()
message(STATUS "skull: removed ${removed_volume_mm3} mm^3, thrust ${thrust_N} N, torque ${torque_Nmm} N mm")
