# gp_module(NAME <name> [DEPS <targets>...] [TEST_DEPS <targets>...])
#   Builds common/<name>/*.cpp into the library gp_<name>, with the project's
#   common/ folder on the include path, and common/<name>/tests/*.cpp into the
#   test executable test_<name> registered with CTest.
#
# gp_tool(NAME <name> DEPS <targets>...)
#   Builds tools/<name>/main.cpp into the executable <name> in bin/.
set(CMAKE_RUNTIME_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/bin")

function(gp_module)
  cmake_parse_arguments(M "" "NAME" "DEPS;TEST_DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cpp")
  if(sources)
    add_library(gp_${M_NAME} STATIC ${sources})
    set(scope PUBLIC)
  else()
    add_library(gp_${M_NAME} INTERFACE)
    set(scope INTERFACE)
  endif()
  target_include_directories(gp_${M_NAME} ${scope} "${PROJECT_SOURCE_DIR}/common")
  target_link_libraries(gp_${M_NAME} ${scope} ${M_DEPS})
  if(sources)
    target_link_libraries(gp_${M_NAME} PRIVATE gp_warnings)
    if(GP_UNITY_BUILD)
      set_target_properties(gp_${M_NAME} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
      # GCC warns of a class that holds a type of its file's anonymous
      # namespace wherever that file is not the unit's main file, which in a
      # unity build none is.
      target_compile_options(gp_${M_NAME} PRIVATE -Wno-subobject-linkage)
    endif()
  endif()

  file(GLOB tests CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/tests/*.cpp")
  if(GP_BUILD_TESTS AND tests)
    add_executable(test_${M_NAME} ${tests})
    set_target_properties(test_${M_NAME} PROPERTIES
      RUNTIME_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/tests")
    target_link_libraries(test_${M_NAME} PRIVATE gp_${M_NAME} ${M_TEST_DEPS}
      gp_testing gp_catch_main gp_warnings)
    add_test(NAME ${M_NAME} COMMAND test_${M_NAME}
      WORKING_DIRECTORY "${CMAKE_BINARY_DIR}")
  endif()
endfunction()

function(gp_tool)
  cmake_parse_arguments(T "" "NAME" "DEPS" ${ARGN})
  add_executable(${T_NAME} "${CMAKE_CURRENT_SOURCE_DIR}/main.cpp")
  target_link_libraries(${T_NAME} PRIVATE ${T_DEPS} gp_warnings)
  gp_cold_code(${T_NAME})
endfunction()

# gp_cold_code(<target>)
#   Compiles <target> at -O1 instead of the build type's -O3: for code that
#   runs once per stage (the command line, reading specs, writing the report
#   page), whose compile time -O3 doubles for nothing. CLI11's header alone
#   costs 7 s of CPU per unit at -O3 (its validators are global objects built
#   in every unit) and 4 s at -O1. The results are the same bits: GCC
#   reorders no floating-point operation at any level (no -ffast-math, and
#   -ffp-contract=off), as the goldens and the demo's outputs, compared byte
#   for byte, show (BENCHMARKS.md, "Build time of the stages"). Hot loops stay
#   in the rooms built at -O3.
function(gp_cold_code target)
  if(CMAKE_BUILD_TYPE MATCHES "^(Release|RelWithDebInfo)$")
    target_compile_options(${target} PRIVATE -O1)
  endif()
endfunction()
