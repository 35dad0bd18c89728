# libFuzzer targets of tests/fuzz (option UAVIP_FUZZ, clang only; scripts/fuzz.sh).
# Every library is compiled with coverage instrumentation and ASan + UBSan, the
# targets link libFuzzer's main. Each target links the one library it reads with;
# --as-needed keeps shared libraries nothing calls (OMPL, FCL for fuzz_yaml) out of
# the binary: a YAML or JSON reader must not load a planner.
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "UAVIP_FUZZ=ON needs clang (CXX=clang++-14; scripts/fuzz.sh)")
endif()
add_compile_options(-O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined)
add_link_options(-fsanitize=address,undefined)

# uavip_fuzz_target(NAME LIBRARIES...): fuzz_NAME from tests/fuzz/fuzz_NAME.cpp.
function(uavip_fuzz_target name)
  add_executable(fuzz_${name} ${PROJECT_SOURCE_DIR}/tests/fuzz/fuzz_${name}.cpp)
  target_compile_options(fuzz_${name} PRIVATE ${UAVIP_WARNINGS})
  target_link_libraries(fuzz_${name} PRIVATE ${ARGN})
  target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer LINKER:--as-needed)
endfunction()
