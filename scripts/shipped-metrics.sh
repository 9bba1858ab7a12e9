#!/usr/bin/env bash
# Runs every shipped scene (scenes/**/*.ron) once and writes OUT/digest.txt: each scene's
# metrics.json without its wall-clock fields (wall_time_s, each effect's seconds). Runs are
# deterministic, so two builds that simulate the same physics give identical digests:
#
#   git checkout A && scripts/shipped-metrics.sh out/metrics-a
#   git checkout B && scripts/shipped-metrics.sh out/metrics-b
#   diff out/metrics-a/digest.txt out/metrics-b/digest.txt
#
# Usage: scripts/shipped-metrics.sh OUT [KES_CLOTH_BINARY]   (default: the release build)
# Takes about 10 minutes on 2 cores (the tablecloths and the folded cloth are the long runs).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/shipped-metrics.sh OUT [KES_CLOTH_BINARY]}
bin=${2:-}
if [ -z "$bin" ]; then
  cargo build --release --quiet
  bin=target/release/kes-cloth
fi
mkdir -p "$out"
: > "$out/digest.txt"
for scene in scenes/*.ron scenes/*/*.ron; do
  name=$(echo "${scene#scenes/}" | sed 's#/#_#g; s#\.ron$##')
  echo "running $scene" >&2
  "$bin" run "$scene" --quiet --out "$out/$name" > "$out/$name.log"
  { echo "== $name"; grep -v -e '"wall_time_s"' -e '"seconds"' "$out/$name/metrics.json"; } >> "$out/digest.txt"
done
echo "wrote $out/digest.txt" >&2
