#!/bin/sh
# Random-design campaign of issue 11: builds N random designs (sharp bends, near contacts,
# crossings, random channel widths, holes, backboards) on grbl-router and grbl-laser through
# the library exactly as `skinpath build` does, and checks each program as
# `skinpath check PROGRAM --machine SAME` would (no flags). Every build must either succeed
# and check clean (no finding above info) or be refused with a message naming the design
# file. Prints the tally of outcomes; failing designs are printed in full.
#
# Usage: scripts/campaign.sh [DESIGNS] [SEED] [LOG]
#   DESIGNS  random designs (default 1000, i.e. 2000 builds), SEED a u64 (default the CI
#   seed 0x5EED0011 = 1592590353), LOG the output file (default campaign-SEED.log).
# CI runs the same test with a handful of cases (tests/fuzz/jobs_props.rs).
set -eu
n=${1:-1000}
seed=${2:-1592590353}
log=${3:-campaign-$seed.log}
cd "$(dirname "$0")/.."
SKINPATH_RANDOM_BUILDS=$n SKINPATH_RANDOM_SEED=$seed \
    cargo test --release --test fuzz jobs_props::random_designs -- --nocapture >"$log" 2>&1 || true
grep -E '^\s+[0-9]+  |random builds:|did not check clean' "$log"
