# uavip_read_packages(VAR): the package names of scripts/packages.txt (comments and
# blank lines dropped), the one list scripts/setup.sh installs.
function(uavip_read_packages var)
  file(STRINGS ${PROJECT_SOURCE_DIR}/scripts/packages.txt lines)
  set(names "")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "#.*" "" line "${line}")
    string(STRIP "${line}" line)
    if(line)
      list(APPEND names ${line})
    endif()
  endforeach()
  set(${var} ${names} PARENT_SCOPE)
endfunction()
