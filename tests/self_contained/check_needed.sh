#!/usr/bin/env bash
# A shared library is self-contained (docs/fmi.md, "Self-contained binaries"): its NEEDED
# entries are all in the allow-list of the C runtime's basic libraries, and the library
# loads and answers FUNCTION in a process with an empty environment (no LD_LIBRARY_PATH)
# that maps no C++ runtime or protobuf (load_library.c).
#   check_needed.sh LOADER LIBRARY FUNCTION
set -euo pipefail
loader=$1 library=$2 function=$3
allowed=" libc.so.6 libm.so.6 libdl.so.2 libpthread.so.0 ld-linux-x86-64.so.2 librt.so.1 "
status=0
needed=$(readelf -d "$library" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
for entry in $needed; do
  if [[ $allowed != *" $entry "* ]]; then
    echo "$library: needs $entry (allowed:$allowed)"
    status=1
  fi
done
echo "$library: NEEDED $(echo $needed)"
if readelf -d "$library" | grep -q "RUNPATH\|RPATH"; then
  echo "$library: has a run path ($(readelf -d "$library" | sed -n 's/.*PATH.*\[\(.*\)\]/\1/p'))"
  status=1
fi
env -i "$loader" "$library" "$function" || status=1
exit $status
