#!/usr/bin/env bash
# Static checks of docker/ (no container engine runs here, so the images are never built
# by CI; this is what can be checked without one):
# - each Dockerfile starts FROM debian:12 (its build stage) and its RUN lines call scripts/install_deps.sh
#   and scripts/build.sh, the two steps scripts/run_tests.sh (CI) calls too;
# - every scripts/... or /src/... path in a Dockerfile exists in the repository (scripts
#   executable); /src/build/release/X must be where this build puts X (SERVER_EXE);
# - compose.yaml has the services server, excavator and truck, names Dockerfiles that
#   exist, gives the server its token from the environment; the server image listens on
#   0.0.0.0.
# Usage: check_docker_files.sh REPO_DIR BUILD_DIR SERVER_EXE
# Exit 0: all checks passed; 1: a check failed (each failure printed).
set -euo pipefail
if (($# != 3)); then
  echo "usage: $0 REPO_DIR BUILD_DIR SERVER_EXE" >&2
  exit 2
fi
repo=$(realpath "$1")
build=$(realpath "$2")
server_exe=$(realpath "$3")
failures=0
fail() {
  echo "check_docker_files: FAIL: $*" >&2
  failures=$((failures + 1))
}

# Logical lines of a Dockerfile: continuation backslashes joined, comments dropped.
logical_lines() { sed -e '/^[[:space:]]*#/d' "$1" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta'; }

for name in Dockerfile.server Dockerfile.clients; do
  file=$repo/docker/$name
  if [[ ! -f "$file" ]]; then
    fail "docker/$name does not exist"
    continue
  fi
  lines=$(logical_lines "$file")
  grep -m1 -E '^FROM ' <<<"$lines" | grep -qE '^FROM debian:12( AS [a-z]+)?$' || fail "$name: first FROM is not debian:12"
  run_lines=$(grep -E '^RUN ' <<<"$lines" || true)
  for step in scripts/install_deps.sh scripts/build.sh; do
    grep -qF "$step" <<<"$run_lines" || fail "$name: no RUN line calls $step"
    grep -qE "^[[:space:]]*$step( |$)" "$repo/scripts/run_tests.sh" ||
      fail "scripts/run_tests.sh does not call $step (CI and $name would build differently)"
  done
  for path in $(grep -oE '(^|[^A-Za-z0-9_/.-])scripts/[A-Za-z0-9_./-]+' <<<"$lines" | sed -E 's/^[^s]//' | sort -u); do
    [[ -x "$repo/$path" ]] || fail "$name references $path, which is not an executable file in the repository"
  done
  for path in $(grep -oE '/src/[A-Za-z0-9_./-]+' <<<"$lines" | sort -u); do
    rel=${path#/src/}
    if [[ "$rel" == build/release || "$rel" == build/release/* ]]; then
      # Where this build put the server (the image builds the same tree with the
      # release preset, so the path below build/release must match).
      if [[ "$(basename "$rel")" == "$(basename "$server_exe")" ]]; then
        [[ "$build/${rel#build/release/}" == "$server_exe" ]] ||
          fail "$name links $path, but the build puts $(basename "$server_exe") at ${server_exe#"$build"/} below the build directory"
      fi
    elif [[ ! -e "$repo/$rel" ]]; then
      fail "$name references $path, but $rel is not in the repository"
    fi
  done
done
grep -qE '^ENTRYPOINT .*"--listen", "0\.0\.0\.0"' "$repo/docker/Dockerfile.server" ||
  fail "Dockerfile.server: ENTRYPOINT does not listen on 0.0.0.0"

compose=$repo/docker/compose.yaml
if [[ ! -f "$compose" ]]; then
  fail "docker/compose.yaml does not exist"
else
  for service in server excavator truck; do
    grep -qE "^  $service:" "$compose" || fail "compose.yaml: no service '$service'"
  done
  for dockerfile in $(grep -oE 'dockerfile: *[^ ,}]+' "$compose" | sed -E 's/dockerfile: *//' | sort -u); do
    [[ -f "$repo/$dockerfile" ]] || fail "compose.yaml names $dockerfile, which does not exist"
  done
  [[ $(grep -cE 'dockerfile:' "$compose") -eq 3 ]] || fail "compose.yaml: expected 3 build sections"
  server_block=$(sed -n '/^  server:/,/^  [a-z]*:$/p' "$compose")
  grep -qE 'DEMLINK_TOKEN: *\$\{DEMLINK_TOKEN' <<<"$server_block" ||
    fail "compose.yaml: the server's DEMLINK_TOKEN does not come from the environment"
fi

if ((failures > 0)); then
  echo "check_docker_files: $failures check(s) failed" >&2
  exit 1
fi
echo "check_docker_files: docker/ references only existing scripts and paths; the images build as CI does"
