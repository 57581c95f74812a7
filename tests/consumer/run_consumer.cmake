# ctest driver for the three ways a user embeds fabsynth:
#  1. find_package(fabsynth REQUIRED) against the package installed into a scratch prefix (plain
#     settings: no CMAKE_FIND_PACKAGE_PREFER_CONFIG or module path of our own);
#  2. pkg-config against the same prefix, compiling with the system compiler;
#  3. add_subdirectory of the source tree from a parent project built as Debug.
file(REMOVE_RECURSE ${WORK_DIR})
macro(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer step failed (${rc}): ${ARGV}")
  endif()
endmacro()
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/prefix)

# The README's embed example: its cmake block becomes a project, its cpp block app.cpp.
file(READ ${SOURCE_DIR}/README.md readme)
string(REGEX MATCH "<!-- embed-example:[^\n]*\n```cmake\n(.*)\n```\n\n```cpp\n(.*)\n```\n<!-- embed-example:end -->" _ "${readme}")
if(NOT CMAKE_MATCH_1 OR NOT CMAKE_MATCH_2)
  message(FATAL_ERROR "README.md: the embed example (cmake + cpp blocks between the embed-example markers) was not found")
endif()
file(WRITE ${WORK_DIR}/readme_app/CMakeLists.txt "${CMAKE_MATCH_1}\n")
file(WRITE ${WORK_DIR}/readme_app/app.cpp "${CMAKE_MATCH_2}\n")

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
run(${CMAKE_COMMAND} -S ${WORK_DIR}/readme_app -B ${WORK_DIR}/readme_app/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/readme_app/build)
execute_process(COMMAND ${WORK_DIR}/readme_app/build/app WORKING_DIRECTORY ${WORK_DIR}/readme_app RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK_DIR}/readme_app/slice.png)
  message(FATAL_ERROR "the README example did not run as documented (exit ${rc}, slice.png missing?)")
endif()

find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CXX_COMPILER c++ REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${WORK_DIR}/prefix/share/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs fabsynth OUTPUT_VARIABLE pc_flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not know the installed fabsynth")
endif()
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
run(${CXX_COMPILER} ${SOURCE_DIR}/tests/consumer/main.cpp ${pc_flags} -o ${WORK_DIR}/pkgconfig_consumer)
run(${WORK_DIR}/pkgconfig_consumer)

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer/subdir -B ${WORK_DIR}/subdir -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Debug -DFABSYNTH_SOURCE_DIR=${SOURCE_DIR})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/subdir)
run(${WORK_DIR}/subdir/consumer)
foreach(tool voxelize fem_solve curve_patterns foam_slicer)
  if(NOT EXISTS ${WORK_DIR}/prefix/bin/${tool})
    message(FATAL_ERROR "cmake --install did not install the tool ${tool}")
  endif()
endforeach()
