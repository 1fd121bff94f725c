#!/usr/bin/env bash
# CTest fixture of the demo tests (tests/cli/CMakeLists.txt): runs the reduced demo once into
# DIR/out and keeps its standard output, standard error and exit status beside it (DIR/stdout,
# DIR/stderr, DIR/exit_code) for the tests to read; they assert on them, so this script fails
# only when it cannot run the demo at all.
#
#   demo_fixture.sh DEMO_SH EDX SHARED_DATA DIR
set -u
demo="$1" edx="$2" shared="$3" dir="$4"
rm -rf "$dir" && mkdir -p "$dir" || exit 1
bash "$demo" --quick --jobs 2 --edx "$edx" --shared "$shared" --out "$dir/out" \
  >"$dir/stdout" 2>"$dir/stderr" </dev/null
echo "$?" >"$dir/exit_code"
