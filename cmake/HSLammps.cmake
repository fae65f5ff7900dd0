# Locate LAMMPS headers + library and detect which LAMMPS API they expose.
#
#   -DLAMMPS_SOURCE_DIR=<lammps>/src   use that tree's headers; library from
#                                      -DLAMMPS_LIBRARY=... or found beside it
#   default: headers from .cache/lammps-headers/src (full set, from Debian's
#            lammps source package; created by scripts/setup.sh) FIRST, then
#            /usr/include/lammps; library /usr/lib/<multiarch>/liblammps.so
#
# Provides:
#   hs::lammps_headers  INTERFACE: include dirs, MPI, LAMMPS_SIZES + API macros
#   hs::lammps          INTERFACE: hs::lammps_headers + liblammps
#
# API macros (always HS_LAMMPS_API_DETECTED=1, see src/HARDSPHERE/hs_compat.h):
#   HS_LAMMPS_NEW_NEIGH_API=1  neighbor.h declares add_request()   (>= 24Mar2022)
#   HS_LAMMPS_NEW_COMM_API=1   comm.h declares forward_comm(Fix *)  (>= 24Mar2022)
#   HS_LAMMPS_ALWAYS_EXCEPTIONS=1  exceptions.h has get_universe(): errors are
#                              always exceptions, src/main.cpp takes LAMMPS'
#                              2023+ main() with its handlers (4Feb2025)
#   HS_LAMMPS_VERSION_NUMBER=YYYYMMDD  from version.h (information only)
# Modify::n_post_force -> n_post_force_any and the skin added to custom list
# cutoffs need no macro: hs_compat.h handles them by overload resolution and
# lmp->num_ver (so that drop-in builds, without our CMake, get them right).

set(LAMMPS_SOURCE_DIR "" CACHE PATH "LAMMPS src/ tree to compile against (optional)")
set(LAMMPS_LIBRARY "" CACHE FILEPATH "LAMMPS library to link (optional)")
set(LAMMPS_SIZES "LAMMPS_SMALLBIG" CACHE STRING
  "LAMMPS integer size macro the library was built with (LAMMPS_SMALLBIG|LAMMPS_BIGBIG|LAMMPS_SMALLSMALL)")

find_package(MPI REQUIRED COMPONENTS CXX)

if(LAMMPS_SOURCE_DIR)
  get_filename_component(_hs_src "${LAMMPS_SOURCE_DIR}" ABSOLUTE)
  if(NOT EXISTS "${_hs_src}/lammps.h")
    message(FATAL_ERROR "LAMMPS_SOURCE_DIR=${_hs_src} contains no lammps.h")
  endif()
  set(HS_LAMMPS_INCLUDE_DIRS "${_hs_src}")
  if(NOT LAMMPS_LIBRARY)
    get_filename_component(_hs_top "${_hs_src}" DIRECTORY)
    find_library(HS_FOUND_LAMMPS_LIBRARY
      NAMES lammps lammps_mpi lammps_serial
      PATHS "${_hs_src}" "${_hs_top}/build" "${_hs_top}/build/lib" "${_hs_top}/lib"
      NO_DEFAULT_PATH)
    if(NOT HS_FOUND_LAMMPS_LIBRARY)
      message(FATAL_ERROR "No liblammps found beside ${_hs_src}; set -DLAMMPS_LIBRARY=...")
    endif()
    set(_hs_lib "${HS_FOUND_LAMMPS_LIBRARY}")
  else()
    set(_hs_lib "${LAMMPS_LIBRARY}")
  endif()
else()
  set(_hs_cache "${CMAKE_CURRENT_SOURCE_DIR}/.cache/lammps-headers/src")
  if(NOT EXISTS "${_hs_cache}/lammps.h")
    message(WARNING "${_hs_cache} missing: run scripts/setup.sh "
      "(Debian's liblammps-dev alone lacks fmt/, neigh_request.h, lammpsplugin.h, ...)")
  endif()
  set(HS_LAMMPS_INCLUDE_DIRS "${_hs_cache}" /usr/include/lammps)
  if(LAMMPS_LIBRARY)
    set(_hs_lib "${LAMMPS_LIBRARY}")
  else()
    if(CMAKE_LIBRARY_ARCHITECTURE)
      set(_hs_lib "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/liblammps.so")
    else()
      set(_hs_lib "/usr/lib/x86_64-linux-gnu/liblammps.so")
    endif()
  endif()
endif()
if(NOT EXISTS "${_hs_lib}")
  message(FATAL_ERROR "LAMMPS library ${_hs_lib} does not exist")
endif()
set(HS_LAMMPS_LIBRARY "${_hs_lib}")

# ---- API check: first header dir that has the file wins (same as the compiler)
function(_hs_find_header name outvar)
  foreach(d IN LISTS HS_LAMMPS_INCLUDE_DIRS)
    if(EXISTS "${d}/${name}")
      set(${outvar} "${d}/${name}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "LAMMPS header ${name} not found in ${HS_LAMMPS_INCLUDE_DIRS}")
endfunction()

_hs_find_header(neighbor.h _hs_neighbor_h)
_hs_find_header(comm.h _hs_comm_h)
_hs_find_header(exceptions.h _hs_exceptions_h)
_hs_find_header(version.h _hs_version_h)
file(READ "${_hs_neighbor_h}" _hs_txt)
if(_hs_txt MATCHES "add_request[ \t]*\\(")
  set(HS_LAMMPS_NEW_NEIGH_API 1)
else()
  set(HS_LAMMPS_NEW_NEIGH_API 0)
endif()
file(READ "${_hs_comm_h}" _hs_txt)
if(_hs_txt MATCHES "forward_comm[ \t]*\\([ \t]*(class[ \t]+)?Fix[ \t]*\\*")
  set(HS_LAMMPS_NEW_COMM_API 1)
else()
  set(HS_LAMMPS_NEW_COMM_API 0)
endif()
file(READ "${_hs_exceptions_h}" _hs_txt)
if(_hs_txt MATCHES "get_universe[ \t]*\\(")
  set(HS_LAMMPS_ALWAYS_EXCEPTIONS 1)
else()
  set(HS_LAMMPS_ALWAYS_EXCEPTIONS 0)
endif()
# version.h: #define LAMMPS_VERSION "4 Feb 2025" -> 20250204
file(READ "${_hs_version_h}" _hs_txt)
set(HS_LAMMPS_VERSION_NUMBER 0)
if(_hs_txt MATCHES "LAMMPS_VERSION[ \t]+\"([0-9]+) ([A-Za-z]+) ([0-9]+)\"")
  set(_hs_day ${CMAKE_MATCH_1})
  set(_hs_mon ${CMAKE_MATCH_2})
  set(_hs_year ${CMAKE_MATCH_3})
  set(HS_LAMMPS_VERSION_STRING "${_hs_day} ${_hs_mon} ${_hs_year}")
  set(_hs_months Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec)
  list(FIND _hs_months "${_hs_mon}" _hs_m)
  math(EXPR _hs_num "${_hs_year} * 10000 + (${_hs_m} + 1) * 100 + ${_hs_day}")
  set(HS_LAMMPS_VERSION_NUMBER ${_hs_num})
endif()
unset(_hs_txt)

set(HS_LAMMPS_API_DEFINITIONS HS_LAMMPS_API_DETECTED=1
    HS_LAMMPS_VERSION_NUMBER=${HS_LAMMPS_VERSION_NUMBER})
if(HS_LAMMPS_NEW_NEIGH_API)
  list(APPEND HS_LAMMPS_API_DEFINITIONS HS_LAMMPS_NEW_NEIGH_API=1)
endif()
if(HS_LAMMPS_NEW_COMM_API)
  list(APPEND HS_LAMMPS_API_DEFINITIONS HS_LAMMPS_NEW_COMM_API=1)
endif()
if(HS_LAMMPS_ALWAYS_EXCEPTIONS)
  list(APPEND HS_LAMMPS_API_DEFINITIONS HS_LAMMPS_ALWAYS_EXCEPTIONS=1)
endif()
# apply to every target of this project (incl. pure-math tests)
add_compile_definitions(${HS_LAMMPS_API_DEFINITIONS})

message(STATUS "HARDSPHERE: LAMMPS version: ${HS_LAMMPS_VERSION_STRING} (${HS_LAMMPS_VERSION_NUMBER})")
message(STATUS "HARDSPHERE: LAMMPS headers: ${HS_LAMMPS_INCLUDE_DIRS}")
message(STATUS "HARDSPHERE: LAMMPS library: ${HS_LAMMPS_LIBRARY} (${LAMMPS_SIZES})")
if(HS_LAMMPS_NEW_NEIGH_API)
  message(STATUS "HARDSPHERE: neighbor API: NEW  (add_request in ${_hs_neighbor_h})")
else()
  message(STATUS "HARDSPHERE: neighbor API: OLD  (request()+NeighRequest flags; no add_request in ${_hs_neighbor_h})")
endif()
if(HS_LAMMPS_NEW_COMM_API)
  message(STATUS "HARDSPHERE: comm API:     NEW  (forward_comm(Fix *) in ${_hs_comm_h})")
else()
  message(STATUS "HARDSPHERE: comm API:     OLD  (forward_comm_fix(); no forward_comm(Fix *) in ${_hs_comm_h})")
endif()
if(HS_LAMMPS_ALWAYS_EXCEPTIONS)
  message(STATUS "HARDSPHERE: errors:       exceptions always (get_universe() in ${_hs_exceptions_h}): 2023+ main()")
else()
  message(STATUS "HARDSPHERE: errors:       exceptions optional (LAMMPS_EXCEPTIONS): 2021 main()")
endif()
message(STATUS "HARDSPHERE: compile definitions: ${LAMMPS_SIZES};${HS_LAMMPS_API_DEFINITIONS}")

add_library(hs_lammps_headers INTERFACE)
target_include_directories(hs_lammps_headers INTERFACE ${HS_LAMMPS_INCLUDE_DIRS})
target_compile_definitions(hs_lammps_headers INTERFACE ${LAMMPS_SIZES})
target_link_libraries(hs_lammps_headers INTERFACE MPI::MPI_CXX)
add_library(hs::lammps_headers ALIAS hs_lammps_headers)

add_library(hs_lammps INTERFACE)
target_link_libraries(hs_lammps INTERFACE hs_lammps_headers "${HS_LAMMPS_LIBRARY}")
add_library(hs::lammps ALIAS hs_lammps)
