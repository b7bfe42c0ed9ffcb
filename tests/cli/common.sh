# Shared by the CLI test scripts (sourced; they set $cdm to the binary under test).

fail() { echo "FAIL: $*"; exit 1; }

# restart_matches TAG SCENE DIR STEPS ARGS...: SCENE run with ARGS into DIR/full, against
# the same run stopped after STEPS steps (its checkpoint kept as DIR/half.cdmck) and
# restarted from that checkpoint into DIR/split. The particle tables and the final
# checkpoints must be identical, bit for bit.
restart_matches() {
  local tag=$1 scene=$2 dir=$3 steps=$4
  shift 4
  "$cdm" run "$scene" -o "$dir/full" "$@" > /dev/null || fail "$tag: full run"
  "$cdm" run "$scene" -o "$dir/split" "$@" --max-steps "$steps" > /dev/null || fail "$tag: first part"
  [ -s "$dir/split/checkpoint.cdmck" ] || fail "$tag: no checkpoint after --max-steps"
  cp "$dir/split/checkpoint.cdmck" "$dir/half.cdmck"
  "$cdm" run "$scene" -o "$dir/split" "$@" --restart "$dir/half.cdmck" > /dev/null || fail "$tag: restart"
  cmp -s "$dir/full/particles.dat" "$dir/split/particles.dat" || fail "$tag: restarted table differs from the uninterrupted one"
  cmp -s "$dir/full/checkpoint.cdmck" "$dir/split/checkpoint.cdmck" || fail "$tag: final states differ"
}
