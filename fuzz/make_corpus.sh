#!/usr/bin/env bash
# Regenerates the seed corpus in fuzz/corpus from the repository: every scene file
# tracked by git (prefixed with byte 0, the target's scene selector) and small
# checkpoints written by cdm itself (prefixed with byte 1): frictional linear contacts,
# a Hertz-Mindlin pile with rolling resistance, two-way coupled gas (velocity inlet
# and pressure outlet; periodic suspension), mesh contacts, insertion and outlets, and
# moving walls. Rerun it after the checkpoint format or the
# scene schema changes, so the fuzzer starts from inputs that load.
#   fuzz/make_corpus.sh [CDM]     CDM defaults to build/release/app/cdm
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cdm="${1:-$root/build/release/app/cdm}"
[ -x "$cdm" ] || { echo "build cdm first (scripts/build.sh release)" >&2; exit 1; }
out="$root/fuzz/corpus"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/corpus"

n=0
cd "$root"
while read -r scene; do
  grep -q '^\[modules\]' "$scene" || continue
  # A seed places at most 2000 particles per block (the 1e5-sphere benchmark bed would
  # take a minute per execution under the sanitizers); mutation still reaches larger counts.
  { printf '\0'; sed -E 's/^count = [0-9]{5,}$/count = 2000/' "$scene"; } > "$tmp/corpus/scene_$n"
  n=$((n + 1))
done < <(git ls-files '*.toml')

m=0
checkpoint() {  # scene steps [--set ...]: a checkpoint after that many steps
  local scene=$1 steps=$2
  shift 2
  "$cdm" run "$scene" -o "$tmp/run_$m" -q --max-steps "$steps" "$@" > /dev/null
  { printf '\1'; cat "$tmp/run_$m/checkpoint.cdmck"; } > "$tmp/corpus/checkpoint_$m"
  m=$((m + 1))
}
checkpoint verification/cases/slipping_ball/scene.toml 200
checkpoint verification/cases/stacked/scene.toml 200
checkpoint tests/cli/scenes/hertz_pile.toml 2000 --set 'lattices[0].count=[3,3,2]'
checkpoint verification/cases/terminal_velocity_coupled/scene.toml 40 --set 'gas.cells=[2,4,2]'
checkpoint verification/cases/suspension/scene.toml 5 --set 'lattices[0].count=[3,3,3]'
checkpoint tests/cli/scenes/mesh_pile.toml 3000 --set 'lattices[0].count=[4,4,2]'
checkpoint tests/cli/scenes/feed_and_drain.toml 3000 --set 'lattices[0].count=[4,4,2]'
checkpoint tests/cli/scenes/moving_walls.toml 2000 --set 'random_particles[0].count=40'

rm -rf "$out"
mv "$tmp/corpus" "$out"
echo "fuzz/corpus: $n scenes, $m checkpoints ($(du -sb "$out" | cut -f1) bytes)"
