# TestBmsimImportHostile.cmake - `bmsim import` on hostile inputs (Docs/Reliability.md), run by
# ctest as
#   cmake -DBMSIM=<bmsim> -DWORK_DIR=<scratch folder> -P TestBmsimImportHostile.cmake
# Each case is a small file written here; bmsim must exit 1 or 2 within the time bound, print a
# message naming the problem, and leave no output or temporary file. The full corpus (NIfTI,
# DICOM, ...) runs in the BMIO unit tests (Testing/Logic/IO/TestHostileInput.cxx).
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/bmExpectRefused.cmake)
foreach(var BMSIM WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "TestBmsimImportHostile.cmake needs -D${var}=...")
  endif()
endforeach()
set(dir "${WORK_DIR}/hostile")
file(REMOVE_RECURSE "${dir}")
file(MAKE_DIRECTORY "${dir}/in" "${dir}/out")

# 4 x 4 x 4 voxels of short, hex for file(WRITE ... HEX) is not available: use ASCII encoding.
string(REPEAT "-1000 " 64 ascii_voxels)
set(nrrd_ok "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\nencoding: ascii\n")

# hostile(<name> <expected message> <content>): write in/<name> and run the import on it.
function(hostile name needle content)
  file(WRITE "${dir}/in/${name}" "${content}")
  run_import("${name}" "${needle}" ${ARGN})
endfunction()

function(run_import name needle)
  execute_process(COMMAND "${BMSIM}" import "${dir}/in/${name}" --out "${dir}/out/v.nrrd" --quiet
                          --resolution 16 ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr TIMEOUT 30)
  file(GLOB left "${dir}/out/*" "${dir}/out/.*")
  bm_check_refused(${name} "${needle}" "${rc}" "${stdout}" "${stderr}" ${left})
endfunction()

hostile(4d.nrrd "4-D"
  "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 4 4 2\nspacings: 1 1 1 1\nencoding: ascii\n\n")
hostile(nan-spacing.nrrd "non-finite voxel spacing"
  "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspacings: nan 1 1\nencoding: ascii\n\n${ascii_voxels}")
hostile(huge.nrrd "more than the"
  "NRRD0004\ntype: short\ndimension: 3\nsizes: 100000 100000 100000\nspacings: 1 1 1\nencoding: raw\n\n")
hostile(passwd.mha "absolute path"
  "NDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\nElementSpacing = 1 1 1\nElementDataFile = /etc/passwd\n")
hostile(dotdot.nhdr "'..'"
  "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\nencoding: raw\ndata file: ../../x.raw\n\n")
hostile(devzero.nhdr "is a device"
  "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\nencoding: raw\ndata file: /dev/zero\n\n"
  --allow-outside-data)
hostile(truncated.mha "truncated"
  "NDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\nElementSpacing = 1 1 1\nElementDataFile = LOCAL\nxx")
hostile(is-nrrd.mha "NRRD file, not a MetaImage" "${nrrd_ok}\n${ascii_voxels}")
hostile(uchar.nrrd "8-bit"
  "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\nencoding: ascii\n\n${ascii_voxels}")
string(REPEAT "k:=v\n" 20000 many)
hostile(many-lines.nrrd "more than 4096 lines" "NRRD0004\n${many}type: short\n\n")
hostile(text.nii "NIfTI" "not an image at all, but longer than three hundred and forty-eight bytes ${ascii_voxels}")

# A FIFO as input: refused at once, not read (it would block).
execute_process(COMMAND mkfifo "${dir}/in/fifo.nrrd" RESULT_VARIABLE rc)
if(rc EQUAL 0)
  run_import(fifo.nrrd "FIFO")
endif()

# The output equal to the input: refused, the input untouched.
file(WRITE "${dir}/out/ct.nrrd" "${nrrd_ok}\n${ascii_voxels}")
file(SHA256 "${dir}/out/ct.nrrd" before)
execute_process(COMMAND "${BMSIM}" import "${dir}/out/ct.nrrd" --out "${dir}/out/ct.nrrd" --quiet
                RESULT_VARIABLE rc ERROR_VARIABLE stderr TIMEOUT 30)
file(SHA256 "${dir}/out/ct.nrrd" after)
if(NOT rc EQUAL 1 OR NOT before STREQUAL after)
  message(FATAL_ERROR "import X --out X: exit ${rc}, input changed: ${before} -> ${after}\n${stderr}")
endif()
string(FIND "${stderr}" "is the input" at)
if(at EQUAL -1)
  message(FATAL_ERROR "import X --out X: the message does not say 'is the input':\n${stderr}")
endif()
message(STATUS "import X --out X: exit ${rc}: ${stderr}")
