#!/bin/sh
# Runs the decoder fuzzer for a bounded time on the committed seed corpus (read only); new inputs
# go to WORK/new, crashing inputs to WORK/artifacts (libFuzzer prints the reproducer command).
# usage: run_fuzzer.sh FUZZER SEED_CORPUS WORK SECONDS
set -eu
fuzzer=$1 seeds=$2 work=$3 seconds=$4
if [ ! -x "$fuzzer" ]; then
  echo "fuzzer $fuzzer is not built (cmake --build builds it with the rest)"
  exit 1
fi
mkdir -p "$work/new" "$work/artifacts"
exec "$fuzzer" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=3072 -max_len=16384 \
  -artifact_prefix="$work/artifacts/" -print_final_stats=1 "$work/new" "$seeds"
