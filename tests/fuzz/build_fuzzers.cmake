# Fuzz.Build: configures (once) and builds the libFuzzer targets with clang. Arguments: CLANGXX,
# SOURCE_DIR (tests/fuzz/targets), BUILD_DIR.
if(NOT CLANGXX OR NOT EXISTS "${CLANGXX}")
  message(FATAL_ERROR "clang++ was not found: the fuzz targets need clang and libFuzzer "
                      "(Debian packages clang and libclang-rt-14-dev; tools/setup installs them)")
endif()
if(NOT EXISTS ${BUILD_DIR}/CMakeCache.txt)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${BUILD_DIR} -DCMAKE_CXX_COMPILER=${CLANGXX}
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    file(REMOVE ${BUILD_DIR}/CMakeCache.txt)
    message(FATAL_ERROR "configuring the fuzz targets failed (${rc})")
  endif()
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} -j 1 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the fuzz targets failed (${rc}); is libclang-rt-14-dev (libFuzzer) installed?")
endif()
