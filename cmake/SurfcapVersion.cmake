# The version string baked into every tool (--version) and every output's provenance.
find_package(Git QUIET)
set(SURFCAP_GIT_DESCRIBE "")
if(GIT_FOUND AND EXISTS ${CMAKE_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --tags --always --dirty
                  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
                  OUTPUT_VARIABLE SURFCAP_GIT_DESCRIBE OUTPUT_STRIP_TRAILING_WHITESPACE
                  ERROR_QUIET)
endif()
if(SURFCAP_GIT_DESCRIBE STREQUAL "")
  set(SURFCAP_GIT_DESCRIBE "unknown")
endif()
set(SURFCAP_VERSION_STRING "${PROJECT_VERSION}+${SURFCAP_GIT_DESCRIBE}")
configure_file(${CMAKE_SOURCE_DIR}/lib/surfcap/core/version.cpp.in
               ${CMAKE_BINARY_DIR}/generated/version.cpp @ONLY)
