#!/bin/sh
# Fixture of the report tests: the small generated customer
# (testdata/customers/small-shirt) through make fit, with the run without
# adaptation (NO_ADAPT=1) so that the report has its before/after pictures,
# and a marker on 1.5 m of fabric (FABRIC_WIDTH).
#   scripts/tests/make_report_fit.sh BIN_DIR OUT_DIR
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$2"
exec make --no-print-directory -f "$root/pipelines/fit.mk" CUSTOMER="$root/testdata/customers/small-shirt" \
  OUT="$2" BIN="$1" NO_ADAPT=1 THREADS=2 FABRIC_WIDTH=1.5
