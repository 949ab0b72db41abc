#!/bin/sh
# Installs the C ABI component of a DEMLink build into a temporary prefix, then builds and
# runs a program against the installed tree twice: a CMake project with
# find_package(DEMLink), and a C program compiled with pkg-config's flags; then installs
# the C++ client and builds a C++ project against it (find_package(DEMLink COMPONENTS
# client)), runs it alone and, when SERVER_EXE is given, against a real server; then
# installs the Modelica package and builds against its Resources alone as a tool does; then
# installs the Python client and imports it from there (when DEMLINK_PYTHON names a
# python3 with google.protobuf).
# Usage: run_install_test.sh BUILD_DIR SOURCE_DIR VERSION [SERVER_EXE]
set -eu
build=$1
source=$2
version=$3
server_exe=${4:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" --component c_abi > "$work/install.log"
test -f "$work/prefix/include/demlink/demlink_c.h"
ls "$work"/prefix/lib*/libdemlink_c.so.1 > /dev/null

# 1. CMake: find_package(DEMLink) -> DEMLink::c
cmake -S "$source/tests/install/consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  > "$work/configure.log"
cmake --build "$work/consumer" > "$work/build.log"
libdir=$(dirname "$(ls "$work"/prefix/lib*/libdemlink_c.so.1 | head -n 1)")
LD_LIBRARY_PATH="$libdir" "$work/consumer/consumer" "$version"

# 2. pkg-config
export PKG_CONFIG_PATH="$libdir/pkgconfig"
test "$(pkg-config --modversion demlink_c)" = "$version"
# shellcheck disable=SC2046
cc -std=c99 -Wall -Werror -o "$work/consumer_pc" "$source/tests/install/consumer/consumer.c" \
  $(pkg-config --cflags --libs demlink_c)
LD_LIBRARY_PATH="$libdir" "$work/consumer_pc" "$version"

# 3. The C++ client: its headers must compile without protoc's output, so the consumer
#    sees only the installed include directory.
cmake --install "$build" --prefix "$work/prefix" --component client >> "$work/install.log"
test -f "$work/prefix/include/demlink/client/client.hpp"
if ls "$work"/prefix/include/demlink/v1 > /dev/null 2>&1; then
  echo "generated protobuf headers were installed" >&2
  exit 1
fi
cmake -S "$source/tests/install/cpp_consumer" -B "$work/cpp_consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  > "$work/cpp_configure.log"
cmake --build "$work/cpp_consumer" > "$work/cpp_build.log" || { cat "$work/cpp_build.log"; exit 1; }
"$work/cpp_consumer/cpp_consumer"
if [ -n "$server_exe" ]; then
  DEMLINK_TEST_TIMEOUT=60 bash "$source/tests/python/run_with_server.sh" "$server_exe" env "$work/cpp_consumer/cpp_consumer"
fi

# 4. The Modelica package from its install location, as a Modelica tool uses it: the
#    consumer compiled with its Resources/Include only and linked with -ldemlink_c from
#    Resources/Library/linux64 (that directory as the run path), run with no environment.
cmake --install "$build" --prefix "$work/prefix" --component modelica >> "$work/install.log"
resources="$work/prefix/share/modelica/DEMLink/Resources"
test -f "$work/prefix/share/modelica/DEMLink/package.mo"
test -f "$resources/Include/demlink_modelica.h"
cc -std=c99 -Wall -Werror -o "$work/consumer_modelica" "$source/tests/install/consumer/consumer.c" \
  -I"$resources/Include" -L"$resources/Library/linux64" -ldemlink_c -Wl,-rpath,"$resources/Library/linux64"
env -u LD_LIBRARY_PATH "$work/consumer_modelica" "$version"

# 5. The Python client from its install location (Debian's python3-protobuf).
if [ -n "${DEMLINK_PYTHON:-}" ]; then
  cmake --install "$build" --prefix "$work/prefix" --component python >> "$work/install.log"
  PYTHONPATH="$work/prefix/lib/python3/dist-packages" "$DEMLINK_PYTHON" -c "
import demlink_client, os
from demlink.v1 import protocol_pb2
assert demlink_client.__file__.startswith('$work/prefix'), demlink_client.__file__
assert protocol_pb2.__file__.startswith('$work/prefix'), protocol_pb2.__file__
m = protocol_pb2.ClientMessage()
m.declarations_done.SetInParent()
assert demlink_client.encode_frame(m) == bytes([2, 0x2a, 0])
print('python client imported from', os.path.dirname(demlink_client.__file__))
"
fi
echo "install test passed"
