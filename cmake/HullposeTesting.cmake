# hullpose_add_test(<name> SOURCES <src>... [LIBS <lib>...] [LABELS <label>...] [WORKING_DIRECTORY <dir>])
#   A Catch2 executable registered with CTest. Every test carries the label "unit" unless
#   LABELS says otherwise ("integration", "system", "gpu", ...); CI's sanitizer pass runs "unit".
#   The target `unit_tests` builds the "unit" tests' executables and nothing else: the sanitizer
#   build (make test-asan) compiles only what it runs. A "unit" test added by plain add_test names
#   the executable it runs with add_dependencies(unit_tests <target>).
# hullpose_add_bench(<name> SOURCES <src>... [LIBS <lib>...])
#   A Google Benchmark executable whose results tools/bench/run-bench.sh prints as JSON lines.
add_custom_target(unit_tests)
function(hullpose_add_test name)
  cmake_parse_arguments(T "" "WORKING_DIRECTORY" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE hullpose_catch_main ${T_LIBS})
  target_compile_definitions(${name} PRIVATE HULLPOSE_SHARED_DIR="${HULLPOSE_SHARED_DIR}"
                                             HULLPOSE_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                             HULLPOSE_BINARY_DIR="${PROJECT_BINARY_DIR}")
  hullpose_target_warnings(${name})
  if(NOT T_LABELS)
    set(T_LABELS unit)
  endif()
  if(NOT T_WORKING_DIRECTORY)
    set(T_WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  endif()
  add_test(NAME ${name} COMMAND ${name} WORKING_DIRECTORY ${T_WORKING_DIRECTORY})
  set_tests_properties(${name} PROPERTIES LABELS "${T_LABELS}")
  if("unit" IN_LIST T_LABELS)
    add_dependencies(unit_tests ${name})
  endif()
endfunction()

set_property(GLOBAL PROPERTY HULLPOSE_BENCHES "")
function(hullpose_add_bench name)
  cmake_parse_arguments(B "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${B_SOURCES})
  target_link_libraries(${name} PRIVATE hullpose_bench_main ${B_LIBS})
  target_compile_definitions(${name} PRIVATE HULLPOSE_SHARED_DIR="${HULLPOSE_SHARED_DIR}"
                                             HULLPOSE_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                             HULLPOSE_BINARY_DIR="${PROJECT_BINARY_DIR}")
  hullpose_target_warnings(${name})
  set_property(GLOBAL APPEND PROPERTY HULLPOSE_BENCHES ${name})
endfunction()
