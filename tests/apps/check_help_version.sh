#!/usr/bin/env bash
# One program's command-line conventions (server/cli/include/demlink/cli/command_line.hpp):
# --help exits 0 and prints the usage; --version exits 0 and prints
# "<name> <project version> (git <revision>)"; an unknown option exits 2 with "error: ".
#   check_help_version.sh PROGRAM NAME VERSION
set -uo pipefail
program=$1 name=$2 version=$3
failed=0
fail() { echo "FAIL: $name: $*"; failed=1; }

help=$("$program" --help 2>&1); rc=$?
[[ $rc -eq 0 ]] || fail "--help exited $rc"
[[ $help == *"Usage: $name"* ]] || fail "--help prints no 'Usage: $name': $help"

out=$("$program" --version 2>&1); rc=$?
[[ $rc -eq 0 ]] || fail "--version exited $rc"
[[ $out =~ ^"$name $version (git "[^\)]+")"$ ]] || fail "--version printed '$out', expected '$name $version (git <revision>)'"

out=$("$program" --no-such-option 2>&1); rc=$?
[[ $rc -eq 2 ]] || fail "--no-such-option exited $rc, expected 2"
[[ $out == *"error: "*"--no-such-option"* ]] || fail "--no-such-option: no error naming it: $out"

((failed == 0)) && echo "$name: --help, --version and a bad option behave"
exit $failed
