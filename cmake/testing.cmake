# uavip_test(NAME SOURCES ... DEPS ... [LABELS label]): one GoogleTest binary test_NAME
# per module, its tests discovered into ctest. LABELS heavy: real clouds and the
# bridge, left out of the sanitizer run (scripts/test.sh).
function(uavip_test name)
  cmake_parse_arguments(T "" "LABELS" "SOURCES;DEPS" ${ARGN})
  add_executable(test_${name} ${T_SOURCES})
  target_compile_options(test_${name} PRIVATE ${UAVIP_WARNINGS})
  target_link_libraries(test_${name} PRIVATE ${T_DEPS} GTest::gtest_main)
  target_compile_definitions(test_${name} PRIVATE
    UAVIP_SOURCE_DIR="${PROJECT_SOURCE_DIR}" UAVIP_BINARY="$<TARGET_FILE:uavip>")
  if(T_LABELS)
    gtest_discover_tests(test_${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 900 LABELS ${T_LABELS})
  else()
    gtest_discover_tests(test_${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
  endif()
endfunction()
