#!/usr/bin/env bash
# Runs every benchmark executable (build/bin/bench-*) in turn; each prints its figures and a
# final JSON line. Benchmarks are long: they are never part of `make test`.
set -euo pipefail
bin="$1"
shopt -s nullglob
benches=("$bin"/bench-*)
if [[ ${#benches[@]} -eq 0 ]]; then
  echo "no benchmarks built" >&2; exit 1
fi
for b in "${benches[@]}"; do
  echo "=== $(basename "$b")"
  "$b"
done
