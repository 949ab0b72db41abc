# The win64 client side, cross-built as part of this (Linux) build when DEMLINK_WIN64 is on
# (default: when Debian's mingw-w64 with POSIX threads and wine64 are installed):
# scripts/build_win64.sh builds it into <build>/win64 on every build (ninja there decides
# what is out of date). Its products, for the FMU packaging (client/fmu), the Modelica
# package's Resources/Library/win64 (below) and the tests under wine (tests/windows):
#   DEMLINK_WIN64_FMU_LIBRARY, DEMLINK_WIN64_C_LIBRARY (+ DEMLINK_WIN64_C_IMPORT_LIBRARY),
#   DEMLINK_WIN64_FMU_MASTER, DEMLINK_WIN64_LOAD_CHECK; DEMLINK_WINE runs them.
find_program(DEMLINK_MINGW_CXX x86_64-w64-mingw32-g++-posix)
find_program(DEMLINK_WINE NAMES wine64 wine PATHS /usr/lib/wine)
find_program(DEMLINK_MINGW_OBJDUMP x86_64-w64-mingw32-objdump)
if(DEMLINK_MINGW_CXX AND DEMLINK_WINE AND DEMLINK_MINGW_OBJDUMP)
  set(demlink_win64_default ON)
else()
  set(demlink_win64_default OFF)
endif()
option(DEMLINK_WIN64 "Cross-build the win64 client libraries and test them under wine" ${demlink_win64_default})
if(NOT DEMLINK_WIN64)
  return()
endif()
if(NOT DEMLINK_MINGW_CXX OR NOT DEMLINK_WINE OR NOT DEMLINK_MINGW_OBJDUMP)
  message(FATAL_ERROR "DEMLINK_WIN64 needs x86_64-w64-mingw32-g++-posix, its objdump and wine64 "
                      "(scripts/install_deps.sh)")
endif()

set(DEMLINK_WIN64_DIR ${CMAKE_BINARY_DIR}/win64)
set(DEMLINK_WIN64_FMU_LIBRARY ${DEMLINK_WIN64_DIR}/demlink_fmu.dll)
set(DEMLINK_WIN64_C_LIBRARY ${DEMLINK_WIN64_DIR}/demlink_c.dll)
set(DEMLINK_WIN64_C_IMPORT_LIBRARY ${DEMLINK_WIN64_DIR}/demlink_c.lib)
set(DEMLINK_WIN64_FMU_MASTER ${DEMLINK_WIN64_DIR}/fmu_master.exe)
set(DEMLINK_WIN64_LOAD_CHECK ${DEMLINK_WIN64_DIR}/fmu_load_check.exe)
add_custom_target(demlink_win64 ALL
  COMMAND ${PROJECT_SOURCE_DIR}/scripts/build_win64.sh ${DEMLINK_WIN64_DIR}
  BYPRODUCTS ${DEMLINK_WIN64_FMU_LIBRARY} ${DEMLINK_WIN64_C_LIBRARY} ${DEMLINK_WIN64_C_IMPORT_LIBRARY}
             ${DEMLINK_WIN64_FMU_MASTER} ${DEMLINK_WIN64_LOAD_CHECK}
  COMMENT "Cross-building the win64 client side in ${DEMLINK_WIN64_DIR}"
  USES_TERMINAL VERBATIM)
