#!/usr/bin/env bash
# The result of one hard case on the MPI backend, from the file hard_case_mpi wrote:
#   mpi_result.sh RESULTS CASE SWEEP    (exit 0 when its line says PASS)
set -u
line=$(grep -m1 "^HARD $2 $3 mpi: " "$1") || { echo "no result for $2 $3 in $1"; exit 1; }
echo "$line"
[[ $line == "HARD $2 $3 mpi: PASS"* ]]
