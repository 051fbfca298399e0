#!/usr/bin/env bash
# Runs every bundled example and copies its report.json (and the analyze JSON) into DIR, so two
# builds can be compared byte for byte: tools/report_snapshot.sh /tmp/before, change, then
# tools/report_snapshot.sh /tmp/after && diff -r /tmp/before /tmp/after.
# Needs the release binary and the plugin libraries: cargo build --release --workspace.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: tools/report_snapshot.sh DIR}
mkdir -p "$dir"
bin=target/release/ecles
for run in examples/*.ron; do
  name=$(basename "$run" .ron)
  out=$(mktemp -d)
  "$bin" run "$run" --quiet --out "$out" > /dev/null 2>&1
  echo "exit $?" > "$dir/$name.exit"
  [ -f "$out/report.json" ] && cp "$out/report.json" "$dir/$name.report.json"
  for f in "$out"/*; do
    case "$f" in *.json) ;; *) sha256sum < "$f" | cut -d' ' -f1 > "$dir/$name.$(basename "$f").sha256" ;; esac
  done
  "$bin" analyze "$run" --json > "$dir/$name.analyze.json" 2> /dev/null
  rm -rf "$out"
done
echo "snapshot of $(ls examples/*.ron | wc -l) examples in $dir"
