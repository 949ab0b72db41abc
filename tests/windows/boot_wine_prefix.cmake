# Creates or updates the wine prefix WINEPREFIX with `WINE wineboot --init` and checks that
# wine runs a program in it; fails with wine's own output when it cannot start.
#   cmake -DWINE=/usr/lib/wine/wine64 -DWINEPREFIX=<dir> -P boot_wine_prefix.cmake
set(ENV{WINEPREFIX} "${WINEPREFIX}")
set(ENV{WINEDEBUG} "-all")
execute_process(COMMAND ${WINE} wineboot --init RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 540)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "wine could not boot the prefix ${WINEPREFIX} (${WINE} wineboot --init: ${result}):\n${out}${err}")
endif()
execute_process(COMMAND ${WINE} cmd /c echo wine-ready RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 120)
if(NOT result EQUAL 0 OR NOT out MATCHES "wine-ready")
  message(FATAL_ERROR "wine cannot run a program in ${WINEPREFIX} (${WINE} cmd /c echo: ${result}):\n${out}${err}")
endif()
message(STATUS "wine prefix ${WINEPREFIX} ready")
