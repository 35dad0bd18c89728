# uavip_module(NAME SOURCES ... DEPS ... SYSTEM_DEPS ...): one static library
# uavip_NAME per module (docs/ARCHITECTURE.md, "Modules and what they may use"),
# compiled with UAVIP_WARNINGS. DEPS are public; SYSTEM_DEPS (third-party libraries
# whose headers are SYSTEM, so their warnings are not ours) private.
function(uavip_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPS;SYSTEM_DEPS" ${ARGN})
  add_library(uavip_${name} STATIC ${M_SOURCES})
  # Installed (README "Install and link"): include/ holds uavip/, include/uavip/ planners/.
  target_include_directories(uavip_${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}> $<INSTALL_INTERFACE:include> $<INSTALL_INTERFACE:include/uavip>)
  target_compile_options(uavip_${name} PRIVATE ${UAVIP_WARNINGS})
  target_link_libraries(uavip_${name} PUBLIC ${M_DEPS})
  if(M_SYSTEM_DEPS)
    target_link_libraries(uavip_${name} PRIVATE ${M_SYSTEM_DEPS})
  endif()
  uavip_unity_build(uavip_${name})
endfunction()

# uavip_system_library(NAME INCLUDES dirs... LIBRARIES libs... DEFINITIONS defs...): an
# INTERFACE target uavip_NAME for a package without a usable imported target; its
# include directories are SYSTEM.
function(uavip_system_library name)
  cmake_parse_arguments(L "" "" "INCLUDES;LIBRARIES;DEFINITIONS" ${ARGN})
  add_library(uavip_${name} INTERFACE)
  target_include_directories(uavip_${name} SYSTEM INTERFACE ${L_INCLUDES})
  target_link_libraries(uavip_${name} INTERFACE ${L_LIBRARIES})
  if(L_DEFINITIONS)
    target_compile_definitions(uavip_${name} INTERFACE ${L_DEFINITIONS})
  endif()
endfunction()

# uavip_unity_build(targets...): with UAVIP_UNITY_BUILD, compiles each target's sources as
# one unity source (CMake UNITY_BUILD), so their shared headers are parsed and their inline
# functions compiled once per target instead of once per source (benchmarks/README.md,
# "Build time"). Sources in one target must then not define the same name in an anonymous
# namespace.
function(uavip_unity_build)
  if(UAVIP_UNITY_BUILD)
    set_target_properties(${ARGN} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 0)
  endif()
endfunction()
