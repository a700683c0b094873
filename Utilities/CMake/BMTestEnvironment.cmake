# BMTestEnvironment.cmake - environment for tests that start ParaView, Mesa, Qt or PoCL.
#
# bm_paraview_test_environment(<out-var>) sets <out-var> to BM_TEST_ENV (Testing/CMakeLists.txt:
# caches in the build tree) plus an XDG_RUNTIME_DIR in the build tree, created now with mode 0700
# as Qt requires, so that no test writes under $HOME or warns about the runtime directory.
function(bm_paraview_test_environment out)
  set(runtime_dir "${CMAKE_BINARY_DIR}/Testing/runtime")
  file(MAKE_DIRECTORY "${runtime_dir}")
  file(CHMOD "${runtime_dir}" DIRECTORY_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
  set(env ${BM_TEST_ENV})
  list(FILTER env EXCLUDE REGEX "^XDG_RUNTIME_DIR=")
  list(APPEND env "XDG_RUNTIME_DIR=${runtime_dir}")
  set(${out} "${env}" PARENT_SCOPE)
endfunction()
