#!/usr/bin/env bash
# The benches' rule for bad input (bench/bench_main.h), checked on every bench without loading a real part:
#   BENCH --help              the usage on stdout, exit 0
#   BENCH --bogus             the mistake and the usage on stderr, exit 2
#   BENCH (a missing part)    one line "BENCH: ..." on stderr, exit 1 (bench_part and bench_sphere take no argument:
#                             for them it is a usage mistake, exit 2)
#   BENCH (an ill-formed number)  a usage mistake, exit 2
# and nothing on stdout but the usage (no work started). Prints one line per failure; exits 1 on any.
#   test/bench_bad_input.sh BENCH_DIR   (the folder holding the bench executables)
set -u

[ $# -eq 1 ] || { echo "usage: $0 BENCH_DIR" >&2; exit 2; }
dir=$(cd "$1" && pwd) || exit 2
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2  # relative part names resolve to nothing here

# bench, the exit code, the arguments: a part that is not there (1), an ill-formed number (2).
cases="
bench_cycle_time        1 nosuch.stl
bench_cycle_time        1 featuretype.STEP nosuch.stl
bench_finishing         1 nosuch.stl
bench_finishing         2 --level x
bench_finishing_checks  1 raster nosuch.stl
bench_finishing_checks  2 raster nosuch.stl --stepover x
bench_holes             1 nosuch.stl
bench_holes             2 --resolution 1mm
bench_part              2 nosuch.stl
bench_roughing          1 nosuch.stl
bench_setup             1 4 nosuch.stl
bench_setup             2 x
bench_simulation        1 nosuch.stl
bench_simulation        2 --lines x
bench_sphere            2 nosuch.stl
bench_surface_finishing 1 nosuch.stl
bench_visibility        1 accuracy nosuch.stl
bench_visibility        2 judge ANC101.stp x
bench_volume_visibility 1 nosuch.stl 2
bench_volume_visibility 2 ANC101.stp x
"

# What the rule puts on stdout and stderr for each exit code.
declare -A rule=([0]="the usage on stdout alone" [1]="one line on stderr, nothing on stdout"
                 [2]="the mistake and the usage on stderr, nothing on stdout")
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# check BENCH CODE ARGS...: the exit code and what the rule puts on stdout and stderr.
check() {
  local bench=$1 want=$2
  shift 2
  local code
  timeout 20 "$dir/$bench" "$@" >out 2>err
  code=$?
  local what="$bench $*: exit $code"
  if [ "$code" -eq 124 ]; then fail "$bench $*: no answer in 20 s (did it load a part?)"; return; fi
  if [ "$code" -ne "$want" ]; then fail "$what, not $want ($(head -c 200 err | head -n 1))"; return; fi
  case $want in
    0) head -n 1 out | grep -q "^usage: $bench" && [ ! -s err ] ;;
    1) [ "$(wc -l <err)" -eq 1 ] && grep -q "^$bench: " err && [ ! -s out ] ;;
    2) grep -q "^$bench: " err && grep -q "^usage: $bench" err && [ ! -s out ] ;;
  esac || fail "$what but not ${rule[$want]}"
}

benches=$(echo "$cases" | awk 'NF { print $1 }' | sort -u)
for bench in $benches; do
  if [ ! -x "$dir/$bench" ]; then
    fail "$bench: not in $dir"
    continue
  fi
  check "$bench" 0 --help
  check "$bench" 0 -h
  check "$bench" 2 --bogus
done
while read -r -a words; do
  [ ${#words[@]} -gt 0 ] && [ -x "$dir/${words[0]}" ] && check "${words[@]}"
done <<<"$cases"
for exe in "$dir"/bench_*; do
  name=$(basename "$exe")
  [ -x "$exe" ] && ! echo "$benches" | grep -qx "$name" && fail "$name: no case in $0"
done

[ "$failures" -eq 0 ] && echo "bench_bad_input: $(echo "$benches" | wc -l) benches answer bad input by the rule"
[ "$failures" -eq 0 ]
