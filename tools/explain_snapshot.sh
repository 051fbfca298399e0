#!/usr/bin/env bash
# Runs `ecles explain` on the first twelve parameters of every bundled example (names from
# `ecles analyze --json`'s structure), as text and JSON, without and with a move (3, 1, −1, …,
# one value per coordinate), and writes each output with its exit code into DIR, so two builds
# can be compared byte for byte: tools/explain_snapshot.sh /tmp/before, change, then
# tools/explain_snapshot.sh /tmp/after && diff -r /tmp/before /tmp/after.
# Needs the release binary and the plugin libraries: cargo build --release --workspace.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: tools/explain_snapshot.sh DIR}
mkdir -p "$dir"
bin=target/release/ecles
for run in examples/*.ron; do
  name=$(basename "$run" .ron)
  params=$("$bin" analyze "$run" --json 2>/dev/null | python3 -c '
import json, sys
structure = json.load(sys.stdin)["structure"]
seen = []
for part in ("over", "well", "under"):
    for column in structure[part]["column_names"]:
        param = column.split("[")[0]
        if param not in seen:
            seen.append(param)
print("\n".join(seen[:12]))')
  for p in $params; do
    "$bin" explain "$run" "$p" > "$dir/$name.$p.txt" 2>&1; echo "exit $?" >> "$dir/$name.$p.txt"
    "$bin" explain "$run" "$p" --json > "$dir/$name.$p.json" 2>&1
    coordinates=$("$bin" explain "$run" "$p" --json 2>/dev/null |
      python3 -c 'import json, sys; print(len(json.load(sys.stdin)["picked"]))' 2>/dev/null || echo 1)
    move=$(python3 -c "print(','.join(str(3 - 2 * i) for i in range($coordinates)))")
    "$bin" explain "$run" "$p" --move "$move" > "$dir/$name.$p.move.txt" 2>&1
    echo "exit $?" >> "$dir/$name.$p.move.txt"
    "$bin" explain "$run" "$p" --move "$move" --json > "$dir/$name.$p.move.json" 2>&1
  done
done
echo "explain snapshot of $(ls "$dir"/*.txt | grep -vc '\.move\.txt$') picks in $dir"
