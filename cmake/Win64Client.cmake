# The win64 cross build (scripts/build_win64.sh, toolchain cmake/mingw-w64-x86_64.cmake):
# the client side only, each program and DLL linked statically (only Windows system DLLs):
#   demlink_c.dll (+ import library demlink_c.lib)  the C ABI, for the Modelica package's
#                                                   Resources/Library/win64
#   demlink_fmu.dll   the FMU library (binaries/win64/<modelIdentifier>.dll): the C ABI
#                     and the client compiled in, because Windows resolves a DLL's imports
#                     from the program's folder and PATH, not from the DLL's own folder
#   fmu_master.exe    the FMU test master (tests/fmu), run under wine by tests/windows
#   fmu_load_check.exe  loads both DLLs and checks their version functions
# The protobuf runtime comes from scripts/win64_protobuf.sh (Protobuf_INCLUDE_DIR,
# Protobuf_LIBRARY); code generation uses the host's protoc of the same version.
find_package(Threads REQUIRED)
find_program(Protobuf_PROTOC_EXECUTABLE protoc REQUIRED)
find_package(Protobuf REQUIRED)

# Asio is header-only: its headers from the host, without the rest of the host's /usr/include.
set(DEMLINK_ASIO_INCLUDE ${CMAKE_BINARY_DIR}/asio-include)
file(MAKE_DIRECTORY ${DEMLINK_ASIO_INCLUDE})
file(CREATE_LINK /usr/include/asio.hpp ${DEMLINK_ASIO_INCLUDE}/asio.hpp SYMBOLIC)
file(CREATE_LINK /usr/include/asio ${DEMLINK_ASIO_INCLUDE}/asio SYMBOLIC)

# Windows headers without the min/max macros (std::min, std::max) or the old winsock.h;
# Asio's Windows 10 code paths.
add_library(demlink_win64_flags INTERFACE)
target_compile_definitions(demlink_win64_flags INTERFACE NOMINMAX WIN32_LEAN_AND_MEAN _WIN32_WINNT=0x0A00)
target_link_libraries(demlink_build_flags INTERFACE demlink_win64_flags)
# The DLLs ship inside FMUs and Modelica packages: no symbol tables in a release build.
add_link_options($<$<CONFIG:Release>:-s>)

add_subdirectory(proto)

set(client_dir ${PROJECT_SOURCE_DIR}/client)
# client/src: the C++ client, and the C ABI on it in the c_*.cpp files.
file(GLOB client_sources CONFIGURE_DEPENDS ${client_dir}/src/*.cpp)
file(GLOB c_abi_sources CONFIGURE_DEPENDS ${client_dir}/src/c_*.cpp)
list(REMOVE_ITEM client_sources ${c_abi_sources})

add_subdirectory(${PROJECT_SOURCE_DIR}/core/parallel core_parallel)
add_library(demlink_client STATIC ${client_sources})
target_include_directories(demlink_client PUBLIC ${client_dir}/include)
target_include_directories(demlink_client SYSTEM PRIVATE ${DEMLINK_ASIO_INCLUDE})
target_link_libraries(demlink_client PUBLIC demlink::proto PRIVATE demlink::wire demlink::parallel Threads::Threads ws2_32 mswsock
                                                                 demlink_asio demlink_build_flags)
set_source_files_properties(${client_dir}/src/connection.cpp PROPERTIES COMPILE_OPTIONS -Wno-null-dereference)

add_library(demlink_c SHARED ${c_abi_sources})
target_link_libraries(demlink_c PRIVATE demlink_client demlink_build_flags)
target_compile_definitions(demlink_c PRIVATE DEMLINK_C_BUILDING DEMLINK_C_VERSION="${PROJECT_VERSION}")
# demlink_c.dll and its import library demlink_c.lib: what Library="demlink_c" finds.
set_target_properties(demlink_c PROPERTIES PREFIX "" IMPORT_PREFIX "" IMPORT_SUFFIX .lib)
target_link_options(demlink_c PRIVATE -Wl,--exclude-libs,ALL)

set(fmu_dir ${client_dir}/fmu)
# client/fmu: the FMU library (demlink_fmu.cpp), the packaging tool (not cross-built) and
# the configuration and archive code both use (every other file).
file(GLOB fmu_config_sources CONFIGURE_DEPENDS ${fmu_dir}/*.cpp)
list(REMOVE_ITEM fmu_config_sources ${fmu_dir}/demlink_fmu.cpp ${fmu_dir}/demlink_fmu_tool.cpp)
add_library(demlink_fmu_config STATIC ${fmu_config_sources})
target_include_directories(demlink_fmu_config PUBLIC ${fmu_dir})
target_link_libraries(demlink_fmu_config PRIVATE demlink_build_flags)

# The C ABI compiled in without DEMLINK_C_BUILDING: the FMU DLL exports the fmi2* functions only.
add_library(demlink_fmu SHARED ${fmu_dir}/demlink_fmu.cpp ${c_abi_sources})
target_link_libraries(demlink_fmu PRIVATE demlink_fmu_config demlink_client demlink_build_flags)
target_compile_definitions(demlink_fmu PRIVATE DEMLINK_FMU_BUILDING DEMLINK_C_VERSION="${PROJECT_VERSION}")
set_target_properties(demlink_fmu PROPERTIES PREFIX "")
target_link_options(demlink_fmu PRIVATE -Wl,--exclude-libs,ALL)

add_executable(fmu_master ${PROJECT_SOURCE_DIR}/tests/fmu/fmu_master.cpp)
target_link_libraries(fmu_master PRIVATE demlink_fmu_config demlink_build_flags)

add_executable(fmu_load_check ${PROJECT_SOURCE_DIR}/tests/windows/fmu_load_check.cpp)
target_include_directories(fmu_load_check PRIVATE ${fmu_dir} ${PROJECT_SOURCE_DIR}/tests/fmu)
target_link_libraries(fmu_load_check PRIVATE demlink_build_flags)
