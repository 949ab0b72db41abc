#!/usr/bin/env bash
# The runtime stage of each Dockerfile (its last FROM) must carry every shared library its
# programs load: for each program the stage copies from build/release, every library `ldd`
# resolves is either
# - a file of a Debian package that the stage's `apt-get install` line names (dpkg -S maps
#   the library to its package, `ldd` and dpkg both run on this Debian 12 machine), or
# - one of our own libraries from the build tree that the stage COPYs (libdemlink_c.so).
# So a new library dependency fails here until the Dockerfile installs it.
# Usage: check_runtime_libs.sh REPO_DIR BUILD_DIR
# Exit 0: covered; 1: a library is missing from a runtime stage (each printed).
set -euo pipefail
if (($# != 2)); then
  echo "usage: $0 REPO_DIR BUILD_DIR" >&2
  exit 2
fi
repo=$(realpath "$1")
build=$(realpath "$2")
failures=0
fail() {
  echo "check_runtime_libs: FAIL: $*" >&2
  failures=$((failures + 1))
}

# Logical lines of the last stage: comments dropped, continuation backslashes joined.
runtime_stage() {
  sed -e '/^[[:space:]]*#/d' "$1" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' |
    awk '/^FROM /{stage = ""} {stage = stage $0 "\n"} END {printf "%s", stage}'
}

# Sets `package` to the Debian package owning library file $1; dpkg -S takes seconds, so
# each path is asked once (no subshell, so the cache persists).
declare -A owners=()
owner_of() {
  if [[ -z "${owners[$1]+set}" ]]; then
    local owner
    owner=$(dpkg -S "$(realpath "$1")" 2>/dev/null || dpkg -S "$1" 2>/dev/null || dpkg -S "/usr$1" 2>/dev/null || true)
    owners[$1]=$(head -n1 <<<"$owner" | cut -d: -f1)
  fi
  package=${owners[$1]}
}

for name in Dockerfile.server Dockerfile.clients; do
  stage=$(runtime_stage "$repo/docker/$name")
  [[ "$(grep -m1 -E '^FROM ' <<<"$stage")" == "FROM debian:12-slim" ]] || fail "$name: the runtime stage is not FROM debian:12-slim"
  grep -qE '^USER [a-z]' <<<"$stage" && ! grep -qE '^USER (root|0)$' <<<"$stage" ||
    fail "$name: the runtime stage does not switch to a non-root USER"
  # Packages: the words after `apt-get install` up to the next && (options dropped).
  packages=$(grep -oE 'apt-get install [^&]*' <<<"$stage" | sed -E 's/apt-get install//' | tr ' ' '\n' |
    grep -vE '^(-.*|)$' | sort -u || true)
  [[ -n "$packages" ]] || fail "$name: the runtime stage installs no packages"
  copied=$(grep -E '^COPY --from=build ' <<<"$stage" | tr ' ' '\n' | grep -E '^/src/build/release/' || true)
  programs=()
  libraries=()
  for path in $copied; do
    file=$build/${path#/src/build/release/}
    [[ -e "$file" ]] || { fail "$name copies $path, but $file is not in this build"; continue; }
    if [[ "$file" == *.so* ]]; then libraries+=("$(basename "$file")"); else programs+=("$file"); fi
  done
  ((${#programs[@]} > 0)) || fail "$name: the runtime stage copies no program from build/release"
  for program in "${programs[@]}"; do
    while read -r soname resolved; do
      [[ -n "$resolved" ]] || continue
      if [[ "$resolved" == "$build"/* ]]; then
        printf '%s\n' "${libraries[@]}" | grep -qxF "$soname" ||
          fail "$name: $(basename "$program") loads $soname from the build tree, which the stage does not COPY"
        continue
      fi
      owner_of "$resolved"
      if [[ -z "$package" ]]; then
        fail "$name: $(basename "$program") loads $resolved, which no Debian package owns"
      elif ! grep -qxF "$package" <<<"$packages"; then
        fail "$name: $(basename "$program") loads $soname from package $package, which the runtime stage does not install"
      fi
    done < <(ldd "$program" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3} $1 ~ /^\// {print $1, $1}')
  done
  echo "check_runtime_libs: $name: $(echo $packages | wc -w) packages cover ${#programs[@]} program(s): $(echo $packages)"
done

if ((failures > 0)); then
  echo "check_runtime_libs: $failures check(s) failed" >&2
  exit 1
fi
echo "check_runtime_libs: every runtime stage holds the libraries its programs load"
