#!/bin/sh
# Runs a fuzzer for a bounded time on its committed seed corpus (read only); new inputs go to
# WORK/new, crashing inputs to WORK/artifacts (libFuzzer prints the reproducer command). Further
# arguments are libFuzzer options (-max_len, -dict, ...); the limits below are every target's.
# usage: run_fuzzer.sh FUZZER SEED_CORPUS WORK SECONDS [LIBFUZZER_OPTION...]
set -eu
fuzzer=$1 seeds=$2 work=$3 seconds=$4
shift 4
if [ ! -x "$fuzzer" ]; then
  echo "fuzzer $fuzzer is not built (cmake --build builds it with the rest)"
  exit 1
fi
mkdir -p "$work/new" "$work/artifacts"
# -rss_limit_mb bounds the process, -malloc_limit_mb any one allocation: an input that makes a
# parser allocate past either is reported as a crash, with the input kept.
exec "$fuzzer" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=512 \
  -artifact_prefix="$work/artifacts/" -print_final_stats=1 "$@" "$work/new" "$seeds"
