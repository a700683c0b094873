# bmsim import of a VTK image (.vti, read by VTK's reader): a 5 mm cube of 1500 HU in air (-1000 HU)
# on a 0.5 mm grid, written here as ASCII XML image data (origin 10, 20, 30 mm), imports with the
# cube's volume (125 mm^3 within 5 %) at the cube's place; a .vti without point data and a missing
# file are refused (exit 1, the message naming the problem, no voxmap written); the copy a killed
# import left beside the output is removed. Args: -DBMSIM= -DWORK_DIR=.
set(dir "${WORK_DIR}")
file(REMOVE_RECURSE "${dir}")
file(MAKE_DIRECTORY "${dir}")

# 24^3 points, the cube at indices 7..16 (10 voxels of 0.5 mm).
set(values "")
foreach(k RANGE 23)
  foreach(j RANGE 23)
    set(row "")
    foreach(i RANGE 23)
      if(i GREATER 6 AND i LESS 17 AND j GREATER 6 AND j LESS 17 AND k GREATER 6 AND k LESS 17)
        string(APPEND row " 1500")
      else()
        string(APPEND row " -1000")
      endif()
    endforeach()
    string(APPEND values "${row}\n")
  endforeach()
endforeach()
function(write_vti path pointdata)
  file(WRITE "${path}" "<?xml version=\"1.0\"?>
<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">
  <ImageData WholeExtent=\"0 23 0 23 0 23\" Origin=\"10 20 30\" Spacing=\"0.5 0.5 0.5\">
    <Piece Extent=\"0 23 0 23 0 23\">
      ${pointdata}
      <CellData></CellData>
    </Piece>
  </ImageData>
</VTKFile>
")
endfunction()
write_vti("${dir}/cube.vti" "<PointData Scalars=\"HU\">
        <DataArray type=\"Float32\" Name=\"HU\" format=\"ascii\">
${values}        </DataArray>
      </PointData>")
write_vti("${dir}/empty.vti" "<PointData></PointData>")

# The MetaImage copy a killed import left (a process that no longer runs): removed by this one.
file(WRITE "${dir}/.bmsim-import-copy.tmp-999999999-1.mha" "left by a killed import")
execute_process(COMMAND "${BMSIM}" import "${dir}/cube.vti" --out "${dir}/cube.nrrd" --quiet
                        --resolution 16
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS "${dir}/cube.nrrd")
  message(FATAL_ERROR "import cube.vti (${rc}):\n${out}\n${err}")
endif()
file(GLOB copies "${dir}/.bmsim-import-copy*")
if(copies)
  message(FATAL_ERROR "the import's copies are left: ${copies}")
endif()
if(NOT out MATCHES "read: +[^\n]*cube\\.vti \\(VTK XML image data, read by VTK\\)")
  message(FATAL_ERROR "the report does not name the .vti and its reader:\n${out}")
endif()
if(NOT out MATCHES "voxmap:[^\n]*over \\[([-0-9.]+), ([-0-9.]+)\\]")
  message(FATAL_ERROR "no voxmap box in:\n${out}")
endif()
set(x0 "${CMAKE_MATCH_1}")
set(x1 "${CMAKE_MATCH_2}")
if(NOT out MATCHES "bone volume: ([0-9.]+) mm\\^3")
  message(FATAL_ERROR "no bone volume in:\n${out}")
endif()
set(volume "${CMAKE_MATCH_1}")
message(STATUS "cube.vti: bone ${volume} mm^3, voxmap x from ${x0} to ${x1} mm")
# The cube spans x = 13.25 .. 18.25 mm (voxel centres 13.5 .. 18, half a voxel either side).
if(volume LESS 118.75 OR volume GREATER 131.25 OR x0 LESS 11 OR x0 GREATER 14 OR x1 LESS 17.5
   OR x1 GREATER 21)
  message(FATAL_ERROR "cube.vti: bone ${volume} mm^3 (expected 125 within 5 %), box x ${x0}..${x1}")
endif()

foreach(case "empty.vti;no point scalars" "missing.vti;no such file")
  list(GET case 0 name)
  list(GET case 1 expected)
  execute_process(COMMAND "${BMSIM}" import "${dir}/${name}" --out "${dir}/refused.nrrd" --quiet
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(GLOB left "${dir}/refused*" "${dir}/.bmsim-import-*")
  if(NOT rc EQUAL 1 OR NOT err MATCHES "${expected}" OR left)
    message(FATAL_ERROR "import ${name}: exit ${rc}, expected 1 and '${expected}', left '${left}':\n${err}")
  endif()
endforeach()
file(GLOB left "${dir}/.bmsim-import-*")
if(left)
  message(FATAL_ERROR "the import left its MetaImage copy: ${left}")
endif()
message(STATUS "bmsim import .vti: passed")

# bmsim plan reads the same VTK image (no shoulder in a cube: exit 3 and the report, not an
# unknown file type), keeping the MetaImage copy as DIR/ct.mha for the plan's steps.
execute_process(COMMAND "${BMSIM}" plan "${dir}/cube.vti" --out "${dir}/plan" --quiet
                        --resolution 32
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 3 OR NOT err MATCHES "no glenoid found" OR NOT EXISTS "${dir}/plan/ct.mha" OR
   NOT EXISTS "${dir}/plan/plan_report.md")
  message(FATAL_ERROR "plan cube.vti: exit ${rc} (expected 3, no glenoid, with ct.mha and the "
                      "report):\n${out}\n${err}")
endif()
# The failure's report shows the bone searched (bmFailurePicture.h).
file(READ "${dir}/plan/plan_report.md" report)
if(NOT EXISTS "${dir}/plan/plan_failure.png" OR NOT report MATCHES "\\(plan_failure.png\\)")
  message(FATAL_ERROR "plan cube.vti: no failure picture in the report:\n${report}")
endif()
file(GLOB left "${dir}/plan/.*")
if(left)
  message(FATAL_ERROR "plan cube.vti left temporaries: ${left}")
endif()
